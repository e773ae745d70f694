// Shared pass: the per-pixel surface keys of TAA's own-surface clamp box
// (TaaSettings::taaOwnSurface; issues 12 and 13). Two pixels are on one surface where their keys
// are equal; the box of a pixel takes only its neighbours of its key.
#pragma once
#include <cstdint>

#include "core/frame_data.h"
#include "core/plane.h"
#include "rtd/methods/emitters.h"

namespace rtd {

/// Bit 31 of a key: the pixel is an emitter the method leaves out of its filter (the predicate
/// of excludeEmitters() in passes/emitters.h), so that emitters and non-emitters never share a
/// box (next to a Cycles lamp, whose filtered radiance is 0, the box would reach down to 0).
constexpr uint32_t kTaaEmitterKey = 0x80000000u;

/// Writes the keys of `f` into `out` and returns true, or returns false (leaving `out` as it
/// is) where the frame has nothing that tells surfaces apart: key = (object id * 4 + class)
/// in bits 0-30, as surfaceKeys() (passes/reflection_reprojection.h) keys the Voorhuis clipping,
/// with the object id where the frame has Buffer::ObjectId, the class where `cls` is given
/// (the method classified the surfaces), and kTaaEmitterKey at the emitters that `emitters`
/// excludes (where the frame has Buffer::Emission; nullptr: a method that excludes none).
bool taaSurfaceKeys(const FrameData& f, const EmitterSettings* emitters, const PixelVector<uint8_t>* cls,
                    PixelVector<uint32_t>& out);

}  // namespace rtd
