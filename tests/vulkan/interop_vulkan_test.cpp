// The application's own device and VkBuffers (rtd/vulkan.h) give the same result as host
// memory, both when rtdenoise submits and when it records into the application's command
// buffer; and without any Vulkan driver the backend fails with a clear rtd::Error while the CPU
// backend still works.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "backend/vulkan/context.h"
#include "rtd/vulkan.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// The application's side: a device it created itself, with buffers holding the frame.
struct App {
  vk::Context ctx{DeviceDesc{.backend = Backend::Vulkan}};
  std::vector<vk::DeviceBuffer> buffers;

  VulkanBufferView store(const Image& img) {
    buffers.emplace_back(ctx, img.pixels.size() * 4, true);
    std::memcpy(buffers.back().mapped(), img.pixels.data(), img.pixels.size() * 4);
    const Format f = img.view().format;
    return {buffers.back().handle(), 0, f};
  }
};

TEST(VulkanInterop, ExternalBuffersMatchHostMemory) {
  RTD_REQUIRE_VULKAN();
  App app;
  auto device = createVulkanDevice({app.ctx.instance(), app.ctx.physicalDevice(), app.ctx.device(), app.ctx.queue(),
                                    app.ctx.queueFamily()});
  EXPECT_EQ(device->backend(), Backend::Vulkan);
  auto host = vulkanDevice()->createDenoiser("accumulate");
  auto submitted = device->createDenoiser("accumulate");
  auto recorded = device->createDenoiser("accumulate");

  // The output lies at an offset inside a larger buffer, with padded pixels (RGBA, stride 20).
  const VkDeviceSize outOffset = 256;
  const uint32_t pixelStride = 20;
  vk::DeviceBuffer out1(app.ctx, outOffset + size_t(kWidth) * kHeight * pixelStride, true);
  vk::DeviceBuffer out2(app.ctx, outOffset + size_t(kWidth) * kHeight * pixelStride, true);

  VkCommandPool pool;
  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = app.ctx.queueFamily();
  ASSERT_EQ(vkCreateCommandPool(app.ctx.device(), &pi, nullptr, &pool), VK_SUCCESS);
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  ASSERT_EQ(vkAllocateCommandBuffers(app.ctx.device(), &ai, &cmd), VK_SUCCESS);

  for (const Frame& f : syntheticFrames(4)) {
    Image expected(kWidth, kHeight, 3);
    host->denoise(f.inputs(), expected.view());

    VulkanFrameInputs in{.width = f.width, .height = f.height};
    for (int b = 0; b < kBufferCount; ++b)
      if (f.has(Buffer(b))) in.buffers[b] = app.store(f.buffers[b]);
    in.camera = f.camera;
    const VulkanBufferView o1{out1.handle(), outOffset, Format::Float4, pixelStride, 0};
    const VulkanBufferView o2{out2.handle(), outOffset, Format::Float4, pixelStride, 0};
    denoiseVulkan(*submitted, in, o1);

    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    ASSERT_EQ(vkBeginCommandBuffer(cmd, &bi), VK_SUCCESS);
    denoiseVulkan(*recorded, in, o2, cmd);
    ASSERT_EQ(vkEndCommandBuffer(cmd), VK_SUCCESS);
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    ASSERT_EQ(vkQueueSubmit(app.ctx.queue(), 1, &si, VK_NULL_HANDLE), VK_SUCCESS);
    ASSERT_EQ(vkQueueWaitIdle(app.ctx.queue()), VK_SUCCESS);

    for (const vk::DeviceBuffer* out : {&out1, &out2}) {
      const char* base = static_cast<const char*>(out->mapped()) + outOffset;
      for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
          const float* p = reinterpret_cast<const float*>(base + (size_t(y) * kWidth + x) * pixelStride);
          for (int c = 0; c < 3; ++c) ASSERT_EQ(p[c], expected.at(x, y, c)) << x << "," << y << " c" << c;
          ASSERT_EQ(p[3], 1.0f);
        }
    }
    app.buffers.clear();
  }
  EXPECT_FALSE(submitted->stats().passes.empty());
  vkDestroyCommandPool(app.ctx.device(), pool, nullptr);
}

TEST(VulkanInterop, DenoiseVulkanRejectsACpuDenoiser) {
  auto cpu = Device::create({.backend = Backend::Cpu})->createDenoiser("accumulate");
  VulkanFrameInputs in{.width = 4, .height = 4};
  EXPECT_THROW(denoiseVulkan(*cpu, in, {}), Error);
}

TEST(VulkanDevice, SelectorThatMatchesNothingIsAClearError) {
  RTD_REQUIRE_VULKAN();
  for (const char* selector : {"no-such-gpu", "99"}) {
    try {
      Device::create({.backend = Backend::Vulkan, .vulkanDevice = selector});
      FAIL() << "expected an rtd::Error for selector " << selector;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("no Vulkan device matches '") + selector + "'"), std::string::npos)
          << e.what();
    }
  }
  // By index and by a name substring, the first device is found.
  auto byIndex = Device::create({.backend = Backend::Vulkan, .vulkanDevice = "0"});
  const std::string name = byIndex->name();
  auto byName = Device::create({.backend = Backend::Vulkan, .vulkanDevice = name.substr(0, 4)});
  EXPECT_EQ(byName->name(), name);
}

std::string runCli(const std::string& env, const std::string& args, int& status) {
  const std::string log = ::testing::TempDir() + "rtd_no_vulkan.log";
  const std::string command = env + " \"" RTD_CLI "\" " + args + " > \"" + log + "\" 2>&1";
  status = std::system(command.c_str());
  std::ifstream in(log);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(VulkanDevice, WithoutAnyDriverTheBackendFailsClearlyAndTheCpuStillWorks) {
  // A loader that finds no driver: what a machine without a Vulkan device sees.
  const std::string noDriver = "VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json";
  int status = 0;
  std::string out = runCli(noDriver, "bench --backend vulkan --method accumulate --size 19x11 --frames 1 --warmup 0", status);
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(out.find("no Vulkan device available"), std::string::npos) << out;
  out = runCli(noDriver, "bench --backend cpu --method accumulate --size 19x11 --frames 1 --warmup 0", status);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("total"), std::string::npos) << out;
  out = runCli(noDriver, "devices", status);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("vulkan  unavailable"), std::string::npos) << out;
}

}  // namespace
}  // namespace rtd::test

namespace rtd::test {
namespace {
TEST(VulkanDevice, DenoiserOutlivesItsDevice) {
  RTD_REQUIRE_VULKAN();
  auto denoiser = Device::create({.backend = Backend::Vulkan})->createDenoiser("accumulate");
  const auto frames = syntheticFrames(2);
  Image out(kWidth, kHeight, 3);
  for (const auto& f : frames) denoiser->denoise(f.inputs(), out.view());
  EXPECT_GT(out.at(kWidth / 2, kHeight / 2, 1), 0.0f);
}
}  // namespace
}  // namespace rtd::test
