// Shared pass: the emitter pixels that SVGF and BMFR leave out of their spatial filters
// (EmitterSettings, rtd/methods/emitters.h; issue 12, the emitter halo). The GLSL twins are
// shaders/emitter_guide.comp (SVGF's guide) and bmfr_fit.comp / bmfr_synthesize.comp, which test
// emitterPixel() the same way.
#pragma once
#include <algorithm>
#include <cstddef>

#include "core/frame_data.h"
#include "passes/atrous.h"
#include "rtd/methods/emitters.h"

namespace rtd {

/// A pixel is an emitter where the largest channel of its primary-hit emission exceeds
/// `threshold` (EmitterSettings::emitterThreshold).
inline bool emitterPixel(float r, float g, float b, float threshold) { return std::max(r, std::max(g, b)) > threshold; }

/// An albedo above 1 in some channel is no reflectance: Cycles writes an emissive surface's
/// emission as its Denoising Albedo (a lamp of strength 12: albedo 12), and such a surface has
/// no BSDF, so its radiance less its emission is 0 whatever light reaches it (tests/fixtures/
/// blender_lamp/README.md). Demodulated it is a black pixel that is not black, with an albedo
/// that multiplies whatever the filter gives it.
inline bool reflectanceless(float r, float g, float b) { return std::max(r, std::max(g, b)) > 1.0f; }

/// Whether `s` asks for the exclusion and `frame` can have emitters (it has Buffer::Emission).
inline bool excludesEmitters(const FrameData& frame, const EmitterSettings& s) {
  return s.excludeEmitters && frame.has(Buffer::Emission);
}

/// Makes the emitter pixels "no surface" in the a-trous guide: a zero normal, so w_n, and with
/// it the whole weight, is 0 between an emitter pixel and any other pixel in either direction
/// (the a-trous levels and the spatial-variance window: the pixel keeps its own value). With
/// s.excludeEmitters off, only the emitter pixels whose albedo (Buffer::Albedo) is
/// reflectanceless(): as the sky's pixels, which have no normal, they have nothing to filter
/// (SVGF's default; the renderer's lamps, whose albedo is their base colour, stay in the
/// filter). Does nothing without Buffer::Emission (and, with the setting off, without
/// Buffer::Albedo). Returns the number of pixels excluded.
size_t excludeEmitters(const FrameData& frame, const EmitterSettings& s, AtrousGuide& guide);

/// weight = 0 at emitter pixels, 1 elsewhere (BMFR's least-squares row weights). Call only
/// where excludesEmitters(frame, s). Returns the number of emitter pixels.
size_t emitterWeights(const FrameData& frame, const EmitterSettings& s, Plane& weight);

}  // namespace rtd
