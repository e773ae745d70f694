// rtdenoise — method "accumulate": temporal accumulation with robust reprojection, the first
// stage of SVGF, A-SVGF and BMFR, as a denoiser of its own (a baseline).
#pragma once
#include "rtd/methods/reprojection.h"

namespace rtd {

struct AccumulateSettings {
  static constexpr const char* kMethod = "accumulate";

  /// Floor of the new sample's weight: w = max(1/n, alpha) with n the history length
  /// including the new sample, i.e. a cumulative average that becomes an exponential moving
  /// average once 1/n < alpha (Koskela et al. 2019 Sec. 4.1; SVGF's alpha = 0.2).
  float alpha = 0.2f;
  /// Longest history counted (BMFR stores 8-bit counts: 255).
  int maxHistoryLength = 255;
  /// Divide radiance by albedo before accumulating and multiply after (SVGF demodulation),
  /// so texture detail is not blurred by reprojection. Needs Buffer::Albedo.
  bool demodulate = true;
  ReprojectionSettings reprojection;

  template <class V> void visit(V& v) {
    v("alpha", alpha, "new-sample weight floor, w = max(1/n, alpha) (SVGF, BMFR: 0.2)", Range{0.001, 1});
    v("maxHistoryLength", maxHistoryLength, "history length cap (BMFR: 8-bit, 255)", Range{1, 65535});
    v("demodulate", demodulate, "divide by albedo before accumulation, multiply after");
    reprojection.visit(v);
  }
};

}  // namespace rtd
