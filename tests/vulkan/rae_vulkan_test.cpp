// RAE on Vulkan (lavapipe in CI): the PyTorch fixtures over three frames (the hidden state
// carried), the CPU (oneDNN) on the synthetic scene at sizes that are not multiples of
// 2^(L-1) = 8, the recurrence and its reset, new weights mid-sequence, and bad input.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/rae/rae_fixture.h"
#include "vulkan_test_util.h"
#include "support/test_frames.h"

namespace rtd {
namespace {

/// The synthetic scene's frames with an albedo (the built-in weights read it).
std::vector<Frame> framesWithAlbedo(int count, int w, int h) {
  std::vector<Frame> frames = test::syntheticFrames(count, w, h);
  for (Frame& f : frames)
    if (f[Buffer::Albedo].empty()) f[Buffer::Albedo] = Image(f.width, f.height, 3, 0.5f);
  return frames;
}

// Float32 shaders against float64 PyTorch, through the fixture's 13 convolutions and three
// frames of state (21x13: padded to 24x16): max |a - e| / (1 + |e|) < 1e-5 (2.3e-7 on
// lavapipe; the margin is for GPUs' 2-ulp exp/log and their own summation order).
TEST(RaeVulkan, MatchesPyTorchOverThreeFrames) {
  RTD_REQUIRE_VULKAN();
  for (const char* inputs : {"color_albedo_normal", "color"}) {
    const test::RaeFixture f = test::loadRaeFixture(inputs);
    auto d = test::vulkanDevice()->createDenoiser("rae");
    d->set("weights", f.weights);
    for (size_t t = 0; t < f.frames.size(); ++t)
      EXPECT_LT(test::maxRelativeError(test::denoised(*d, f.frames[t]), f.expected[t]), 1e-5) << inputs << ", frame " << t;
  }
}

// The built-in weights (4 levels) on a moving synthetic sequence, three frames with the state
// carried, at 67x41 (padded to 72x48), 1x1 and 9x16: Vulkan within 1e-5 (relative, as above)
// of the CPU, frame by frame (6.6e-7 on lavapipe).
TEST(RaeVulkan, MatchesCpuAtAnySize) {
  RTD_REQUIRE_VULKAN();
  for (auto [w, h, count] : {std::tuple{test::kWidth, test::kHeight, 3}, {1, 1, 2}, {9, 16, 2}}) {
    auto cpu = Device::create()->createDenoiser("rae");
    auto gpu = test::vulkanDevice()->createDenoiser("rae");
    const std::vector<Frame> frames = framesWithAlbedo(count, w, h);
    for (size_t t = 0; t < frames.size(); ++t) {
      const Image a = test::denoised(*cpu, frames[t]), b = test::denoised(*gpu, frames[t]);
      ASSERT_EQ(b.width, w);
      ASSERT_EQ(b.height, h);
      EXPECT_TRUE(test::allFinite(b));
      EXPECT_LT(test::maxRelativeError(b, a), 1e-5) << w << "x" << h << ", frame " << t;
    }
  }
}

// Checklist 27 on the GPU: identical inputs give different outputs through the hidden state;
// reset(), a camera cut and recurrent = false give the first-frame output again, bit for bit.
TEST(RaeVulkan, HiddenStateChangesTheOutputAndResetClearsIt) {
  RTD_REQUIRE_VULKAN();
  const test::RaeFixture f = test::loadRaeFixture("color_albedo_normal");
  auto d = test::vulkanDevice()->createDenoiser("rae");
  d->set("weights", f.weights);
  const Image first = test::denoised(*d, f.frames[1]);
  const Image second = test::denoised(*d, f.frames[1]);
  EXPECT_GT(test::compare(first, second).maxAbs[0], 1e-3) << "identical inputs, different hidden states";
  d->reset();
  EXPECT_EQ(test::compare(test::denoised(*d, f.frames[1]), first).maxAbs[0], 0.0) << "after reset()";
  FrameInputs cut = f.frames[1].inputs();
  cut.cameraCut = true;
  Image out(f.frames[1].width, f.frames[1].height, 3);
  d->denoise(cut, out.view());
  EXPECT_EQ(test::compare(out, first).maxAbs[0], 0.0) << "on a camera cut";
  d->set("recurrent", "false");
  test::denoised(*d, f.frames[0]);
  EXPECT_EQ(test::compare(test::denoised(*d, f.frames[1]), first).maxAbs[0], 0.0) << "recurrent = false";
}

// New weights mid-sequence rebuild the network (another architecture: the built-in 4 levels,
// then the fixture's 3) and clear the state: the next frame is the new network's first frame.
TEST(RaeVulkan, NewWeightsRebuildTheNetwork) {
  RTD_REQUIRE_VULKAN();
  const test::RaeFixture f = test::loadRaeFixture("color_albedo_normal");
  auto d = test::vulkanDevice()->createDenoiser("rae");
  test::denoised(*d, f.frames[0]);
  test::denoised(*d, f.frames[1]);
  d->set("weights", f.weights);
  EXPECT_LT(test::maxRelativeError(test::denoised(*d, f.frames[0]), f.expected[0]), 1e-5);
}

// The bad-input classes the import sanitizes (NaN, +-Inf, +-1e30 in colour, albedo and
// normal): finite output on every frame, and the GPU's output stays within the CPU tolerance
// of the CPU's (whose hidden states rae_test.cpp inspects), a clean frame after them included.
TEST(RaeVulkan, BadInputStaysFiniteAndMatchesCpu) {
  RTD_REQUIRE_VULKAN();
  std::vector<Frame> frames = framesWithAlbedo(4, 24, 16);
  const float bad[] = {std::nanf(""), INFINITY, -INFINITY, 1e30f, -1e30f};
  int k = 0;
  for (int t = 0; t < 3; ++t)
    for (Buffer b : {Buffer::Color, Buffer::Albedo, Buffer::Normal})
      for (size_t i = 7 + size_t(t); i < frames[size_t(t)][b].pixels.size(); i += 37)
        frames[size_t(t)][b].pixels[i] = bad[k++ % 5];
  auto cpu = Device::create()->createDenoiser("rae");
  auto gpu = test::vulkanDevice()->createDenoiser("rae");
  for (size_t t = 0; t < frames.size(); ++t) {
    const Image a = test::denoised(*cpu, frames[t]), b = test::denoised(*gpu, frames[t]);
    ASSERT_TRUE(test::allFinite(b)) << "frame " << t;
    EXPECT_LT(test::maxRelativeError(b, a), 1e-5) << "frame " << t;
  }
}

}  // namespace
}  // namespace rtd
