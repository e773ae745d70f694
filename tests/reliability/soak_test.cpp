// Issue 21: the short version of the soak (bench/soak/soak.h; scripts/soak.sh runs 1000 frames
// per method per backend): every method on both backends over 60 renderer-made frames in two
// shots (a camera cut) of two sizes (a resize), each with a frame of bad pixels (without the 1e30
// fireflies, whose slow decay in history the full soak covers). Every output must be finite, the
// frames from the 15th of each shot on within a factor 2 of their clean input's mean, and
// resident memory after the first shot may grow by at most 24 MiB (a 64x48 frame of every buffer
// is 0.5 MiB: a leak of a frame's history per frame would pass 24 MiB in the second shot).
#include <gtest/gtest.h>

// Under AddressSanitizer freed blocks wait in its quarantine (256 MiB by default) before reuse,
// so resident memory grows with the bytes freed, not the bytes kept: the bound means nothing
// there. That build finds leaks with LeakSanitizer instead, which names the allocation.
#if defined(__SANITIZE_ADDRESS__)
#define RTD_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RTD_TEST_ASAN 1
#endif
#endif

#ifdef HAVE_RTDENOISE_RENDER
#include "soak/soak.h"
#include "support/backends.h"

namespace rtd::test {
namespace {

TEST(Soak, ShortStreamWithCutsResizesAndBadPixels) {
  soak::Config c;
  c.frames = 60;
  c.shotLength = 30;
  c.shotsPerSize = 1;
  c.badAt = 3;
  c.fireflies = false;
  c.checkFrom = 15;
  c.rssEvery = 5;
  c.warmupFrames = 30;
  c.backends.clear();
  for (Backend b : testBackends())
    if (testDevice(b)) c.backends.push_back(b);
  c.log = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
  const auto results = soak::run(c);
  ASSERT_FALSE(results.empty());
  for (const auto& r : results) {
    const std::string what = r.method + " on " + std::string(backendName(r.backend));
    EXPECT_EQ(r.error, "") << what;
    EXPECT_EQ(r.frames, c.frames) << what;
    EXPECT_EQ(r.nonFiniteFrames, 0) << what;
    EXPECT_EQ(r.unstableFrames, 0) << what;
#ifndef RTD_TEST_ASAN
    EXPECT_LE(r.rssMaxMiB - r.rssBaselineMiB, c.rssBoundMiB) << what;
#endif
  }
}

}  // namespace
}  // namespace rtd::test
#endif
