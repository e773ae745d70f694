// rtdenoise — settings of the shared reprojection pass (SVGF, A-SVGF, BMFR and plain
// accumulation all reproject history the same way; only the consistency tests differ).
#pragma once
#include "rtd/settings_visit.h"

namespace rtd {

/// Which previous-frame samples may be reused. Each of the four bilinear taps around the
/// reprojected position is tested separately (Schied et al. 2017; Koskela et al. 2019);
/// invalid taps get zero weight and the valid ones are renormalized.
struct ReprojectionSettings {
  /// Run the depth test below (SVGF's; BMFR tests world positions instead).
  bool testDepth = true;
  /// Reject a tap when |z_prev - z| > depthTolerance * z + depthGradientScale * |grad z|,
  /// |grad z| being the screen-space depth slope (pixel units). Not given by the papers
  /// (Higginson: "[UNCLEAR]"); 5% relative plus two pixels of slope keeps grazing floors.
  float depthTolerance = 0.05f;
  float depthGradientScale = 2.0f;
  /// Reject a tap when dot(n_prev, n) < normalTolerance (cosine). 0.9 ~ 25 degrees; BMFR's
  /// code uses |dn|^2 < 0.25, i.e. cos > 0.875.
  float normalTolerance = 0.9f;
  /// Reject a tap whose object id differs (SVGF's mesh-id test).
  bool testObjectId = true;
  /// Reject a tap whose world position is farther than positionTolerance (world units) plus
  /// positionFootprints times the pixel's world-space footprint (the distance to its nearest
  /// neighbour's world position per screen axis, the larger axis: distance x pixel angle /
  /// cos(incidence), so it scales with the scene and needs no per-scene tuning). Both 0
  /// disables the test. BMFR's code: an absolute sqrt(0.0016) = 0.04 for Sponza, about 2.5 to 8
  /// footprints at its 720p camera's 3 to 10 m (rtdenoise's BMFR default: 4 footprints).
  float positionTolerance = 0.0f;
  float positionFootprints = 0.0f;
  /// Whether the world-position test is on (the frames' positions are then read).
  bool testsPosition() const { return positionTolerance > 0 || positionFootprints > 0; }
  /// When no bilinear tap is valid, try the 3x3 neighbourhood with the Gaussian kernel of
  /// Higginson Eq. 1.4 (centred and renormalized, see docs/methods/accumulate.md).
  bool fallback3x3 = true;

  template <class V> void visit(V& v) {
    v("testDepth", testDepth, "reject history taps by view depth (SVGF); BMFR tests world positions instead");
    v("depthTolerance", depthTolerance, "relative depth difference that rejects a history tap", Range{0, 1e9});
    v("depthGradientScale", depthGradientScale, "pixels of screen-space depth slope added to the depth tolerance", Range{0, 1e9});
    v("normalTolerance", normalTolerance, "min cosine between current and history normals", Range{-1, 1});
    v("testObjectId", testObjectId, "reject history taps with another object id (SVGF mesh-id test)");
    v("positionTolerance", positionTolerance, "absolute part of the world-position tolerance, world units (BMFR code: 0.04)", Range{0, 1e9});
    v("positionFootprints", positionFootprints,
      "scale-free part of the world-position tolerance, in pixel footprints (world distance to the neighbour pixel); both 0 = off",
      Range{0, 1e9});
    v("fallback3x3", fallback3x3, "3x3 Gaussian fallback when no bilinear tap is valid (Higginson Eq. 1.4)");
  }
};

}  // namespace rtd
