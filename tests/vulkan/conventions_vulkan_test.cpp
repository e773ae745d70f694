// Engine conventions and half-float inputs on the Vulkan backend: the "conventions" pass turns
// the same scene given in each convention into the native output (as on the CPU), and half
// inputs, from host memory or from the application's VkBuffers with odd strides, give exactly
// what float inputs of the same values give.
#include <cstring>

#include "backend/vulkan/context.h"
#include "core/half.h"
#include "rtd/vulkan.h"
#include "support/convention_frames.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

using C = FrameConventions;

synthetic::Scene conventionsVulkanScene() {
  synthetic::Scene s;
  s.gradientSamples = false;  // A-SVGF's; they do not follow the camera's yaw and jitter
  s.width = kWidth;
  s.height = kHeight;
  return s;
}

// Tolerances as on the CPU (tests/core/conventions_test.cpp).
TEST(VulkanConventions, MotionInNdcYUpPointingToCurrent) {
  RTD_REQUIRE_VULKAN();
  expectSameOutput(*vulkanDevice(), conventionsVulkanScene(), motionAs(C::MotionUnits::Ndc, true, true), 1e-5, 4);
}
TEST(VulkanConventions, MotionIncludingJitter) {
  RTD_REQUIRE_VULKAN();
  auto s = conventionsVulkanScene();
  s.jitter = true;
  expectSameOutput(*vulkanDevice(), s, jitteredMotion(s), 1e-5, 4);
}
TEST(VulkanConventions, JitteredCameraWithoutMotionVectors) {
  RTD_REQUIRE_VULKAN();
  auto s = conventionsVulkanScene();
  s.jitter = true;
  expectSameOutput(*vulkanDevice(), s, jitteredCameraOnly(s), 1e-5, 4);
}
TEST(VulkanConventions, ViewSpaceNormals) {
  RTD_REQUIRE_VULKAN();
  auto s = conventionsVulkanScene();
  s.cameraYawSpeed = 0.03f;
  expectSameOutput(*vulkanDevice(), s, viewSpaceNormals(), 1e-5, 4);
}
TEST(VulkanConventions, HardwareDepthOpenGlAndReversedInfinite) {
  RTD_REQUIRE_VULKAN();
  expectSameOutput(*vulkanDevice(), conventionsVulkanScene(), hardwareDepth(openGlProjection(0.1, 100), C::DepthRange::MinusOneToOne),
                   1e-4, 4);
  expectSameOutput(*vulkanDevice(), conventionsVulkanScene(), hardwareDepth(reversedInfiniteProjection(0.1), C::DepthRange::ZeroToOne),
                   1e-5, 4);
}

// The converted frame on Vulkan against the converted frame on the CPU: the backends' usual
// agreement for SVGF (docs/vulkan.md): the conventions pass is the CPU's conversion.
TEST(VulkanConventions, AllConventionsAtOnceMatchTheCpu) {
  RTD_REQUIRE_VULKAN();
  auto s = conventionsVulkanScene();
  s.jitter = true;
  s.cameraYawSpeed = 0.02f;
  const ToEngine steps[] = {jitteredMotion(s), motionAs(C::MotionUnits::Uv, true, false), viewSpaceNormals(),
                            hardwareDepth(reversedInfiniteProjection(0.1), C::DepthRange::ZeroToOne)};
  const ToEngine all = [&](int i, Frame& f, C& c) {
    for (const auto& step : steps) step(i, f, c);  // jittered pixel motion, then in UV with y up
  };
  auto cpu = Device::create();
  const auto a = denoiseSequence(*cpu, "svgf", {}, s, 4, all);
  const auto b = denoiseSequence(*vulkanDevice(), "svgf", {}, s, 4, all);
  for (size_t i = 0; i < a.size(); ++i) expectClose(b[i], a[i], 1e-4, 2e-6, "frame " + std::to_string(i));
}

// Half copies of a frame's float buffers (the float frame rounded to the same values).
struct HalfFrame {
  std::array<std::vector<uint16_t>, kBufferCount> halves;
  explicit HalfFrame(Frame& f) {
    for (int b = 0; b < kBufferCount; ++b) {
      Image& img = f.buffers[b];
      if (img.empty() || Buffer(b) == Buffer::ObjectId) continue;
      halves[b].resize(img.pixels.size());
      floatsToHalves(img.pixels.data(), halves[b].data(), img.pixels.size());
      halvesToFloats(halves[b].data(), img.pixels.data(), img.pixels.size());
    }
  }
};
constexpr Format kHalfFormats[] = {Format::Undefined, Format::Half, Format::Half2, Format::Half3, Format::Half4};

TEST(VulkanHalf, HostHalfInputsAndOutputsMatchFloatOnes) {
  RTD_REQUIRE_VULKAN();
  auto asFloat = vulkanDevice()->createDenoiser("svgf"), asHalf = vulkanDevice()->createDenoiser("svgf");
  for (int i = 0; i < 3; ++i) {
    Frame f = synthetic::makeFrame(conventionsVulkanScene(), i);
    HalfFrame h(f);
    FrameInputs in = f.inputs();
    for (int b = 0; b < kBufferCount; ++b)
      if (!h.halves[b].empty()) in.buffers[b] = {h.halves[b].data(), kWidth, kHeight, kHalfFormats[f.buffers[b].channels]};
    Image floatOut(kWidth, kHeight, 3);
    std::vector<uint16_t> halfOut(size_t(kWidth) * kHeight * 3);
    asFloat->denoise(f.inputs(), floatOut.view());
    asHalf->denoise(in, {halfOut.data(), kWidth, kHeight, Format::Half3});
    for (size_t k = 0; k < halfOut.size(); ++k) ASSERT_EQ(halfOut[k], floatToHalf(floatOut.pixels[k])) << "frame " << i;
  }
}

// Half pixels in the application's VkBuffer: Half3 colour at a 2-byte offset with 6-byte pixels
// and rows padded by one half, the other buffers packed.
TEST(VulkanHalf, ExternalHalfBuffersMatchFloatOnes) {
  RTD_REQUIRE_VULKAN();
  vk::Context ctx{DeviceDesc{.backend = Backend::Vulkan}};
  auto device = createVulkanDevice({ctx.instance(), ctx.physicalDevice(), ctx.device(), ctx.queue(), ctx.queueFamily()});
  auto asFloat = device->createDenoiser("svgf"), asHalf = device->createDenoiser("svgf");
  vk::DeviceBuffer out(ctx, size_t(kWidth) * kHeight * 16, true);
  for (int i = 0; i < 3; ++i) {
    Frame f = synthetic::makeFrame(conventionsVulkanScene(), i);
    HalfFrame h(f);
    std::vector<vk::DeviceBuffer> storage;
    VulkanFrameInputs in{.width = kWidth, .height = kHeight};
    in.camera = f.camera;
    for (int b = 0; b < kBufferCount; ++b) {
      if (h.halves[b].empty()) continue;
      const int nc = f.buffers[b].channels;
      const bool padded = Buffer(b) == Buffer::Color;
      const size_t offset = padded ? 2 : 0, rowStride = size_t(kWidth) * nc * 2 + (padded ? 2 : 0);
      storage.emplace_back(ctx, offset + rowStride * kHeight + 4, true);
      for (int y = 0; y < kHeight; ++y)
        std::memcpy(static_cast<char*>(storage.back().mapped()) + offset + y * rowStride,
                    h.halves[b].data() + size_t(y) * kWidth * nc, size_t(kWidth) * nc * 2);
      in.buffers[b] = {storage.back().handle(), offset, kHalfFormats[nc], 0, uint32_t(rowStride)};
    }
    Image expected(kWidth, kHeight, 4);
    asFloat->denoise(f.inputs(), expected.view());  // ids stay float in both
    storage.emplace_back(ctx, f[Buffer::ObjectId].pixels.size() * 4, true);
    std::memcpy(storage.back().mapped(), f[Buffer::ObjectId].pixels.data(), f[Buffer::ObjectId].pixels.size() * 4);
    in[Buffer::ObjectId] = {storage.back().handle(), 0, Format::Float};
    denoiseVulkan(*asHalf, in, VulkanBufferView{out.handle(), 0, Format::Float4});
    ASSERT_EQ(std::memcmp(out.mapped(), expected.pixels.data(), expected.pixels.size() * 4), 0) << "frame " << i;
  }
}

}  // namespace
}  // namespace rtd::test
