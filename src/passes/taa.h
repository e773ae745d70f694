// Shared pass: temporal anti-aliasing with neighbourhood clamping (Karis 2014): the previous
// output, reprojected bilinearly, is clamped to the min/max box of the current 3x3
// neighbourhood in YCoCg and blended with the current frame.
#pragma once
#include "core/plane.h"
#include "passes/reprojection.h"
#include "rtd/methods/taa.h"

namespace rtd {

class Taa {
 public:
  void resize(int w, int h);
  void reset() { valid_ = false; }
  /// `color` is the current remodulated output; the result goes to `out` and becomes history.
  /// Uses the reprojected positions of `rp` (no consistency tests: the clamp rejects ghosts).
  void run(const Reprojection& rp, const Plane3& color, float alpha, Plane3& out);

 private:
  Plane3 history_;
  Plane3 ycocg_, rowMin_, rowMax_, lo_, hi_;  // the 3x3 box, separably, in YCoCg
  bool valid_ = false;
};

}  // namespace rtd
