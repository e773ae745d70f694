// Engine input conventions (rtd::FrameConventions) to the native ones: the numbers of the
// conversion are computed once per frame here, for both backends, and applied to the imported
// planes right after import (applyConventions on the CPU, the "conventions" pass on Vulkan).
// A frame in the native conventions converts nothing and costs nothing.
#pragma once
#include <array>
#include <cmath>

#include "core/frame_data.h"
#include "rtd/frame.h"

namespace rtd {

/// Depth at (or beyond) an infinite far plane after conversion (FrameConventions::depth).
constexpr float kFarDepth = 1e30f;

struct ConventionTransform {
  /// Motion (native: pixels to the previous position, y down): m' = m * motionScale + motionOffset.
  bool motion = false;
  float motionScale[2] = {1, 1}, motionOffset[2] = {0, 0};
  /// Normals: n' = normalize(normalMatrix * n) (row-major 3x3), zero normals left zero.
  bool normals = false;
  float normalMatrix[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// Hardware depth: ndc = d * ndcScale + ndcOffset, z = (p23 - p33 ndc) / (p32 ndc - p22),
  /// depth = min(|z|, kFarDepth) (p_rc: row r, column c of the depth projection).
  bool depth = false;
  float ndcScale = 1, ndcOffset = 0, p22 = 1, p23 = 0, p32 = 0, p33 = 1;
  /// Jitter of this frame (pixels, y down): the history position derived from the cameras is
  /// shifted by -jitter (jitterCompensated()).
  bool jitter = false;
  float jitterPixels[2] = {0, 0};

  /// Whether any plane is converted.
  bool convertsPlanes() const { return motion || normals || depth; }

  float linearDepth(float d) const {
    const float ndc = d * ndcScale + ndcOffset;
    const float z = std::abs((p23 - p33 * ndc) / (p32 * ndc - p22));
    return z < kFarDepth ? z : kFarDepth;  // also infinity and 0/0
  }
};

/// The conversion for a width x height frame with `camera`. Throws rtd::Error when it needs
/// what the frame lacks (view-space normals without a valid camera), before any work is done.
ConventionTransform conventionTransform(const FrameConventions& c, const Camera& camera, int width, int height,
                                        bool hasNormals);

/// Converts the imported motion, normal and depth planes of `frame` in place (CPU backend);
/// what it stores is 0 or at least kTiny in magnitude, as import's values (core/flush.h).
void applyConventions(const ConventionTransform& t, FrameData& frame);

/// `previous` as the reprojection of a jittered frame must see it: its projection shifted by
/// -jitter pixels, so that the history position it gives (from Buffer::Position, when the frame
/// has no motion vectors) is the unjittered one. Unchanged when t.jitter is false.
Camera jitterCompensated(const Camera& previous, const ConventionTransform& t, int width, int height);

/// The rotation part of camera.worldToCamera, row-major 3x3 (world-space normals to view
/// space: n_view = R n_world, as the learned methods see them); the identity without a valid
/// camera.
std::array<float, 9> worldToViewRotation(const Camera& camera);

}  // namespace rtd
