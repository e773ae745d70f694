// Shared pass: eye reprojection (Gersthofer 2020, Sec. 3.4.2 and 4.2), the exchange of
// view-independent light between the two views of a stereo pair. Each pixel of the target eye
// is carried into the source eye by its world position times the source eye's view-projection
// matrix; the source's 2x2 bilinear taps around the landing point are validated "following the
// principles from temporal accumulation" (object id, normal angle, and here also the depth of
// the point against the source's depth, which rejects occluded points), the valid bilinear
// weights renormalized, and the gathered value blended into the target's. A gather, run once
// per direction. GLSL twin: src/backend/vulkan/shaders/eye_reprojection.comp.
#pragma once
#include <array>
#include <cstddef>

#include "core/frame_data.h"
#include "rtd/methods/reprojection.h"

namespace rtd {

/// Where the world point `p` lands in a view: continuous pixel position (pixel (x, y) has its
/// centre at (x + 0.5, y + 0.5), rows from the top) and its linear view depth; false behind the
/// camera. The renderer's and the sequence format's conventions (rtd/frame.h).
struct ViewProjection {
  std::array<float, 16> worldToCamera, projection;  // row-major, column vectors
  int width = 0, height = 0;
  static ViewProjection of(const Camera& c, int width, int height) { return {c.worldToCamera, c.projection, width, height}; }
  bool project(const float p[3], float& px, float& py, float& depth) const;
};

/// One eye's guide buffers the pass reads (a frame's planes; objectId, depthGradient and
/// `valid` may be null).
struct EyeGuide {
  const std::vector<Plane>* position = nullptr;  ///< world-space position, 3 planes
  const std::vector<Plane>* normal = nullptr;    ///< world-space normal, 3 planes (0: no surface)
  const Plane* depth = nullptr;                  ///< linear view depth
  const Plane* objectId = nullptr;
  const std::vector<Plane>* depthGradient = nullptr;  ///< screen-space depth slope, widens the depth test
  /// Where the source holds no light yet (e.g. an unsampled pixel without history): > 0 = data.
  const Plane* valid = nullptr;
  ViewProjection view;

  static EyeGuide of(const FrameData& f);
};

/// The source taps of one target pixel: up to four (index, weight) with weights summing to 1;
/// count 0 where the point does not reach valid source pixels.
struct EyeTaps {
  int count = 0;
  int32_t index[4];
  float weight[4];
};

/// The validated, renormalized bilinear taps in `source` of target pixel i. Uses the
/// validation settings of temporal reprojection: normalTolerance, testObjectId, testDepth with
/// depthTolerance (relative) and depthGradientScale (pixels of the source's depth slope).
EyeTaps eyeTaps(const EyeGuide& target, const EyeGuide& source, const ReprojectionSettings& s, size_t i);

/// out = (1 - blend) target + blend * gather(source) where the pixel reprojects, target
/// elsewhere (`out` may be `targetLight`). `reprojected` (optional) receives 1 where the
/// pixel was blended, 0 elsewhere. Returns the number of blended pixels.
size_t eyeReproject(const EyeGuide& target, const EyeGuide& source, const ReprojectionSettings& s, float blend,
                    const Plane3& targetLight, const Plane3& sourceLight, Plane3& out, Plane* reprojected = nullptr);

}  // namespace rtd
