// A denoiser whose settings or input changed mid-sequence against one that had them from the
// start, in tests of state allocated on first use.
#pragma once
#include <gtest/gtest.h>

#include <vector>

#include "rtd/rtd.h"

namespace rtd::test {

/// Denoises `frames` with both and expects the same pixels frame by frame (on one backend
/// the arithmetic is the same: bit for bit). `switched` has been reset after its change.
inline void expectRunsAsFresh(Denoiser& switched, Denoiser& fresh, const std::vector<Frame>& frames) {
  for (size_t i = 0; i < frames.size(); ++i) {
    const Frame& f = frames[i];
    Image a(f.width, f.height, 3), b(f.width, f.height, 3);
    switched.denoise(f.inputs(), a.view());
    fresh.denoise(f.inputs(), b.view());
    ASSERT_EQ(a.pixels, b.pixels) << "frame " << i << " after the switch";
  }
}

}  // namespace rtd::test
