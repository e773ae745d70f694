// TNND on Vulkan (lavapipe in CI): the PyTorch fixture, and the CPU on the synthetic scene
// with the built-in weights, with and without the temporal accumulation in front.
#include <gtest/gtest.h>

#include "methods/tnnd/tnnd_fixture.h"
#include "vulkan_test_util.h"

namespace rtd {
namespace {

TEST(TnndVulkan, MatchesPyTorch) {
  RTD_REQUIRE_VULKAN();
  const test::TnndFixture f = test::loadTnndFixture();
  auto d = test::vulkanDevice()->createDenoiser("tnnd");
  d->set("weights", f.weights);
  d->set("iterations", std::to_string(f.iterations));
  Image out(f.frame.width, f.frame.height, 3);
  d->denoise(f.frame.inputs(), out.view());
  EXPECT_LT(test::maxRelativeError(out, f.expected), 1e-3);
}

TEST(TnndVulkan, MatchesCpu) {
  RTD_REQUIRE_VULKAN();
  synthetic::Scene scene;
  scene.width = test::kWidth;
  scene.height = test::kHeight;
  for (bool accumulate : {false, true}) {
    auto cpu = Device::create()->createDenoiser("tnnd");
    auto gpu = test::vulkanDevice()->createDenoiser("tnnd");
    for (auto* d : {cpu.get(), gpu.get()}) d->set("accumulate", accumulate ? "true" : "false");
    for (int i = 0; i < 3; ++i) {
      Frame f = synthetic::makeFrame(scene, i);
      f[Buffer::Albedo] = f[Buffer::Albedo].empty() ? Image(f.width, f.height, 3, 0.5f) : f[Buffer::Albedo];
      Image a(f.width, f.height, 3), b(f.width, f.height, 3);
      cpu->denoise(f.inputs(), a.view());
      gpu->denoise(f.inputs(), b.view());
      EXPECT_LT(test::maxRelativeError(b, a), 1e-3) << "frame " << i << (accumulate ? " with accumulation" : "");
    }
  }
}

}  // namespace
}  // namespace rtd
