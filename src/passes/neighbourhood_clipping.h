// Shared pass: neighbourhood clipping tailored to SVGF (Voorhuis 2018, Sec. 4.2.3). The
// history of a non-diffuse pixel is clipped to the range of the current frame's colours in a
// 5x5 window before the temporal blend, as TAA does (Karis 2014), but the window is read from
// a separable 7x7 Gaussian of the current (noisy, demodulated) frame so that neighbouring
// pixels see coherent ranges. This pass builds the per-pixel box; the shared temporal
// accumulation applies it (AccumulationOptions::clipLow/clipHigh). GLSL twin:
// src/backend/vulkan/shaders/clip_box.comp.
#pragma once
#include <cstdint>

#include "core/plane.h"

namespace rtd {

struct ClipBoxOptions {
  int gaussianRadius = 3;  ///< 7x7 prefilter (Voorhuis)
  float sigma = 1.5f;      ///< of the prefilter, pixels (not given by the paper)
  int windowRadius = 2;    ///< 5x5 window (Voorhuis)
};

/// Per channel, low/high = min/max over the (2 windowRadius + 1)^2 window of G * current, G the
/// separable (2 gaussianRadius + 1)^2 Gaussian (weights normalized; both clamp to the image
/// edge). Where `clip` is given and 0 (diffuse pixels), low = -inf and high = +inf: the
/// history passes unclipped. `scratch` holds the prefiltered image (any size; resized).
///
/// With `surface` (one key per pixel; needs `clip`), the neighbourhood of a pixel is its own
/// surface only: the prefilter at q weighs only taps with q's key (renormalized; the taps still
/// clamp to the image edge) and the window at p takes only pixels with p's key. Neighbours of
/// another surface are not samples of what p may show now, and mixing them in moves the box
/// off p's colours at every silhouette (a specular orb against a background whose specular
/// lobe is black gets its box's top pulled down and its history darkened). Pixels of one key
/// must be all clipped or all not; the box is computed at clipped pixels only.
void clipBox(const Plane3& current, const PixelVector<uint8_t>* clip, const ClipBoxOptions& opt, Plane3& low,
             Plane3& high, Plane3& scratch, const PixelVector<uint32_t>* surface = nullptr);

/// The normalized 1D weights of the prefilter (2 radius + 1 of them), shared with the GPU pass.
void clipGaussianWeights(int radius, float sigma, float* out);

}  // namespace rtd
