// rtdenoise — settings of the shared final temporal anti-aliasing pass (Karis 2014), which
// SVGF and BMFR apply to their remodulated output.
#pragma once
#include "rtd/settings_visit.h"

namespace rtd {

struct TaaSettings {
  /// Run TAA on the output.
  bool taa = true;
  /// Weight of the current frame in the TAA blend (Karis 2014: ~0.1; BMFR code: 0.2).
  float taaAlpha = 0.1f;

  template <class V> void visit(V& v) {
    v("taa", taa, "final TAA with YCoCg 3x3 neighbourhood clamping (Karis 2014)");
    v("taaAlpha", taaAlpha, "weight of the current frame in the TAA blend (Karis 2014: 0.1, BMFR: 0.2)", Range{0.001, 1});
  }
};

}  // namespace rtd
