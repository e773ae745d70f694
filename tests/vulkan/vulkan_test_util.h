// Helpers of the Vulkan backend tests: one lavapipe (or other) device shared by the tests, the
// synthetic scene at a size that is not a multiple of the 16x16 workgroup, and error statistics
// per channel between the CPU and Vulkan results.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

namespace rtd::test {

// 67x41: neither dimension is a multiple of 16, so every shader's bounds checks are exercised.
constexpr int kWidth = 67, kHeight = 41;

/// The Vulkan device of the test run, or null (the test then fails, unless
/// RTD_SKIP_VULKAN_TESTS=1 is set, where it is skipped: CI always has lavapipe).
inline Device* vulkanDevice(std::string* why = nullptr) {
  static std::string error;
  static std::unique_ptr<Device> device = [] {
    try {
      return Device::create({.backend = Backend::Vulkan});
    } catch (const Error& e) {
      error = e.what();
      return std::unique_ptr<Device>();
    }
  }();
  if (why) *why = error;
  return device.get();
}

#define RTD_REQUIRE_VULKAN()                                                                      \
  do {                                                                                            \
    std::string why_;                                                                             \
    if (!::rtd::test::vulkanDevice(&why_)) {                                                      \
      const char* skip_ = std::getenv("RTD_SKIP_VULKAN_TESTS");                                   \
      if (skip_ && std::string(skip_) == "1") GTEST_SKIP() << "no Vulkan device: " << why_;       \
      FAIL() << "no Vulkan device (set RTD_SKIP_VULKAN_TESTS=1 to skip): " << why_;              \
    }                                                                                             \
  } while (0)

/// Max and mean absolute difference per channel of two images of the same size.
struct ErrorStats {
  double maxAbs[4] = {0, 0, 0, 0};
  double meanAbs[4] = {0, 0, 0, 0};
  double maxRef = 0;  ///< largest |reference| value, to state relative tolerances
  int channels = 0;
};

/// The bytes of all the categories of a frame's FrameStats::memory.
inline uint64_t memoryTotal(const FrameStats& stats) {
  uint64_t sum = 0;
  for (const MemoryUse& u : stats.memory) sum += u.bytes;
  return sum;
}

inline ErrorStats compare(const Image& test, const Image& reference, int channels = 3) {
  ErrorStats s;
  s.channels = channels;
  const size_t n = size_t(reference.width) * reference.height;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < channels; ++c) {
      const double r = reference.pixels[i * reference.channels + c];
      const double d = std::abs(double(test.pixels[i * test.channels + c]) - r);
      s.maxAbs[c] = std::max(s.maxAbs[c], d);
      s.meanAbs[c] += d / double(n);
      s.maxRef = std::max(s.maxRef, std::abs(r));
    }
  return s;
}

inline std::string describe(const ErrorStats& s) {
  std::string out;
  for (int c = 0; c < s.channels; ++c)
    out += "ch" + std::to_string(c) + ": max " + std::to_string(s.maxAbs[c]) + " mean " + std::to_string(s.meanAbs[c]) + "; ";
  return out + "max |ref| " + std::to_string(s.maxRef);
}

/// The stated tolerance of the Vulkan backend against the CPU (docs/vulkan.md): per channel,
/// max abs error <= maxRel * max|ref| and mean abs error <= meanRel * max|ref|.
inline void expectClose(const Image& gpu, const Image& cpu, double maxRel, double meanRel, const std::string& what) {
  const ErrorStats s = compare(gpu, cpu);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(s.maxAbs[c], maxRel * s.maxRef) << what << ": " << describe(s);
    EXPECT_LE(s.meanAbs[c], meanRel * s.maxRef) << what << ": " << describe(s);
  }
  EXPECT_GT(s.maxRef, 0.0) << what << ": reference is all zero, the comparison would prove nothing";
}

/// For passes with discrete decisions (FXAA's edge tests, whose inputs differ between the
/// backends by ~1e-6 relative): at most `flippedShare` of the pixels may differ by more than
/// maxRel * max|ref| (a flipped decision); over the others the mean abs error stays <= meanRel *
/// max|ref|.
inline void expectCloseExceptFlips(const Image& gpu, const Image& cpu, double maxRel, double meanRel,
                                   double flippedShare, const std::string& what) {
  const ErrorStats s = compare(gpu, cpu);
  const size_t n = size_t(cpu.width) * cpu.height;
  size_t flipped = 0;
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    double d[3];
    bool off = false;
    for (int c = 0; c < 3; ++c) {
      d[c] = std::abs(double(gpu.pixels[i * gpu.channels + c]) - cpu.pixels[i * cpu.channels + c]);
      off |= d[c] > maxRel * s.maxRef;
    }
    flipped += off;
    if (!off) sum += (d[0] + d[1] + d[2]) / 3.0;
  }
  EXPECT_LE(double(flipped), flippedShare * double(n)) << what << ": " << flipped << " pixels differ; " << describe(s);
  EXPECT_LE(sum / double(n - flipped), meanRel * s.maxRef) << what << ": " << describe(s);
  EXPECT_GT(s.maxRef, 0.0) << what << ": reference is all zero, the comparison would prove nothing";
}

/// Synthetic frames 0..count-1 at the test size.
inline std::vector<Frame> syntheticFrames(int count, int width = kWidth, int height = kHeight) {
  synthetic::Scene scene;
  scene.width = width;
  scene.height = height;
  std::vector<Frame> frames;
  for (int i = 0; i < count; ++i) frames.push_back(synthetic::makeFrame(scene, i));
  return frames;
}

// The SVGF family's Vulkan-against-CPU tolerance (svgf, its variants, A-SVGF's filter), per
// frame and channel: max abs error <= kSvgfMaxRel * max|ref|, mean abs error <= kSvgfMeanRel *
// max|ref|. The CPU a-trous evaluates exp() with a polynomial and 1/x with a refined estimate
// (~1e-7 relative), the GPU with its own exp and division, and the CPU's spatial variance sums in
// double: the filter's weights differ by ~1e-6 relative, which five levels and the feedback loop
// carry on. Measured on lavapipe: max 2e-6 relative (1.1e-5 absolute with max|ref| ~6); the
// tolerance leaves room for GPUs whose exp and division are less exact.
inline constexpr double kSvgfMaxRel = 1e-4, kSvgfMeanRel = 2e-6;

}  // namespace rtd::test
