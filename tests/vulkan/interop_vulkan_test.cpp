// The application's own device, VkBuffers and VkImages (rtd/vulkan.h) give the same result as
// host memory, both when rtdenoise submits and when it records into the application's command
// buffer; and without any Vulkan driver the backend fails with a clear rtd::Error while the CPU
// backend still works.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include <Imath/half.h>

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

// An application image with its memory and a 2D view; destroyed with the test.
struct AppImage {
  VkDevice device = VK_NULL_HANDLE;
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  int width = 0, height = 0, texelBytes = 0;
  AppImage() = default;
  AppImage(const AppImage&) = delete;
  ~AppImage() {
    if (!device) return;
    vkDestroyImageView(device, view, nullptr);
    vkDestroyImage(device, image, nullptr);
    vkFreeMemory(device, memory, nullptr);
  }
};

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to) {
  VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0,
                       nullptr, 1, &b);
}

void createImage(vk::Context& ctx, int w, int h, VkFormat format, int texelBytes, VkImageUsageFlags usage, AppImage& out) {
  out.device = ctx.device();
  out.format = format;
  out.width = w;
  out.height = h;
  out.texelBytes = texelBytes;
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = format;
  ii.extent = {uint32_t(w), uint32_t(h), 1};
  ii.mipLevels = 1;
  ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = usage | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  ASSERT_EQ(vkCreateImage(ctx.device(), &ii, nullptr, &out.image), VK_SUCCESS);
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(ctx.device(), out.image, &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.memoryType(req.memoryTypeBits, false);
  ASSERT_EQ(vkAllocateMemory(ctx.device(), &ai, nullptr, &out.memory), VK_SUCCESS);
  ASSERT_EQ(vkBindImageMemory(ctx.device(), out.image, out.memory, 0), VK_SUCCESS);
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = out.image;
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = format;
  vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  ASSERT_EQ(vkCreateImageView(ctx.device(), &vi, nullptr, &out.view), VK_SUCCESS);
}

// Copies tightly packed texels into the image and leaves it in `layout`.
void uploadImage(vk::Context& ctx, const AppImage& img, const void* texels, VkImageLayout layout) {
  const size_t bytes = size_t(img.width) * img.height * img.texelBytes;
  vk::DeviceBuffer staging(ctx, bytes, true);
  std::memcpy(staging.mapped(), texels, bytes);
  ctx.runOnce([&](VkCommandBuffer cmd) {
    imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy c{};
    c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    c.imageExtent = {uint32_t(img.width), uint32_t(img.height), 1};
    vkCmdCopyBufferToImage(cmd, staging.handle(), img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
    imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, layout);
  });
}

std::vector<char> downloadImage(vk::Context& ctx, const AppImage& img, VkImageLayout layout) {
  const size_t bytes = size_t(img.width) * img.height * img.texelBytes;
  vk::DeviceBuffer staging(ctx, bytes, true);
  ctx.runOnce([&](VkCommandBuffer cmd) {
    imageBarrier(cmd, img.image, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy c{};
    c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    c.imageExtent = {uint32_t(img.width), uint32_t(img.height), 1};
    vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1, &c);
    imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout);
  });
  std::vector<char> out(bytes);
  std::memcpy(out.data(), staging.mapped(), bytes);
  return out;
}

// Every buffer of the frame as the image format an engine would use for it; buffers stored in
// half precision (albedo, roughness) are first rounded to half in the host frame too, so both
// paths see the same values.
struct ImageFrame {
  std::vector<std::unique_ptr<AppImage>> images;
  VulkanFrameInputs inputs;
};

void toImages(vk::Context& ctx, Frame& f, ImageFrame& out) {
  out.inputs = VulkanFrameInputs{.width = f.width, .height = f.height, .camera = f.camera};
  for (int b = 0; b < kBufferCount; ++b) {
    if (!f.has(Buffer(b))) continue;
    Image& src = f.buffers[b];
    const Buffer which = Buffer(b);
    const bool half = which == Buffer::Albedo || which == Buffer::Roughness;
    const bool id = which == Buffer::ObjectId || which == Buffer::MaterialId;
    VkFormat format;
    int channels;  // of the image format
    if (id) format = VK_FORMAT_R32_SINT, channels = 1;
    else if (src.channels == 1) format = half ? VK_FORMAT_R16_SFLOAT : VK_FORMAT_R32_SFLOAT, channels = 1;
    else if (src.channels == 2) format = VK_FORMAT_R32G32_SFLOAT, channels = 2;
    else format = half ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT, channels = 4;
    const int texelBytes = channels * (half ? 2 : 4);
    std::vector<char> texels(size_t(f.width) * f.height * texelBytes, 0);
    for (size_t i = 0; i < size_t(f.width) * f.height; ++i)
      for (int c = 0; c < channels; ++c) {
        float& v = src.pixels[i * src.channels + std::min(c, src.channels - 1)];
        char* dst = texels.data() + i * texelBytes;
        if (c >= src.channels) {
          const float one = 1.0f;
          if (half) {
            const uint16_t h = Imath::half(one).bits();
            std::memcpy(dst + 2 * c, &h, 2);
          } else {
            std::memcpy(dst + 4 * c, &one, 4);
          }
        } else if (id) {
          const int32_t n = int32_t(v);
          std::memcpy(dst, &n, 4);
        } else if (half) {
          const Imath::half h(v);
          v = float(h);  // the host frame sees the same rounded value
          const uint16_t bits = h.bits();
          std::memcpy(dst + 2 * c, &bits, 2);
        } else {
          std::memcpy(dst + 4 * c, &v, 4);
        }
      }
    auto img = std::make_unique<AppImage>();
    createImage(ctx, f.width, f.height, format, texelBytes, VK_IMAGE_USAGE_SAMPLED_BIT, *img);
    // Depth in GENERAL, the others read-only optimal: both sampled layouts work.
    const VkImageLayout layout = which == Buffer::Depth ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    uploadImage(ctx, *img, texels.data(), layout);
    out.inputs.image(which) = {img->view, format, layout};
    out.images.push_back(std::move(img));
  }
}

TEST(VulkanInterop, ExternalImagesMatchHostMemory) {
  RTD_REQUIRE_VULKAN();
  App app;
  auto device = createVulkanDevice({app.ctx.instance(), app.ctx.physicalDevice(), app.ctx.device(), app.ctx.queue(),
                                    app.ctx.queueFamily()});
  for (const char* method : {"accumulate", "bmfr"}) {
    auto host = vulkanDevice()->createDenoiser(method);
    auto gpu32 = device->createDenoiser(method);
    auto gpu16 = device->createDenoiser(method);
    AppImage out32, out16;
    createImage(app.ctx, kWidth, kHeight, VK_FORMAT_R32G32B32A32_SFLOAT, 16, VK_IMAGE_USAGE_STORAGE_BIT, out32);
    createImage(app.ctx, kWidth, kHeight, VK_FORMAT_R16G16B16A16_SFLOAT, 8, VK_IMAGE_USAGE_STORAGE_BIT, out16);
    app.ctx.runOnce([&](VkCommandBuffer cmd) {
      imageBarrier(cmd, out32.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
      imageBarrier(cmd, out16.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
    });
    for (Frame& f : syntheticFrames(3)) {
      // The ids are integers stored as floats in the host frame (read as R32_SINT images here).
      ImageFrame images;
      toImages(app.ctx, f, images);
      Image expected(kWidth, kHeight, 3);
      host->denoise(f.inputs(), expected.view());
      denoiseVulkan(*gpu32, images.inputs, VulkanImageView{out32.view, out32.format, VK_IMAGE_LAYOUT_GENERAL});
      denoiseVulkan(*gpu16, images.inputs, VulkanImageView{out16.view, out16.format, VK_IMAGE_LAYOUT_GENERAL});
      const std::vector<char> got32 = downloadImage(app.ctx, out32, VK_IMAGE_LAYOUT_GENERAL);
      const std::vector<char> got16 = downloadImage(app.ctx, out16, VK_IMAGE_LAYOUT_GENERAL);
      for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
          const size_t i = size_t(y) * kWidth + x;
          const float* p = reinterpret_cast<const float*>(got32.data() + i * 16);
          for (int c = 0; c < 3; ++c) ASSERT_EQ(p[c], expected.at(x, y, c)) << method << " " << x << "," << y << " c" << c;
          ASSERT_EQ(p[3], 1.0f);
          for (int c = 0; c < 4; ++c) {
            Imath::half h;
            uint16_t bits;
            std::memcpy(&bits, got16.data() + i * 8 + 2 * c, 2);
            h.setBits(bits);
            const float want = c < 3 ? expected.at(x, y, c) : 1.0f;
            // Conversion to half in an image store may round either way: within one half ulp.
            ASSERT_NEAR(float(h), want, std::abs(want) * (1.0f / 1024.0f) + 1e-7f) << method << " half " << x << "," << y;
          }
        }
    }
    EXPECT_FALSE(gpu32->stats().passes.empty());
  }
}

TEST(VulkanInterop, UnsupportedImageFormatsAndLayoutsAreClearErrors) {
  RTD_REQUIRE_VULKAN();
  auto denoiser = vulkanDevice()->createDenoiser("accumulate");
  VulkanFrameInputs in{.width = 8, .height = 8};
  // Any non-null handle: validation happens before anything is recorded.
  const VkImageView fake = reinterpret_cast<VkImageView>(uintptr_t(0x1234));
  in.image(Buffer::Color) = {fake, VK_FORMAT_R8G8B8_SRGB, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  const VulkanImageView out{fake, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_LAYOUT_GENERAL};
  auto message = [&](const VulkanImageView& o) {
    try {
      denoiseVulkan(*denoiser, in, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(out).find("buffer 'color': image format"), std::string::npos) << message(out);
  in.image(Buffer::Color) = {fake, VK_FORMAT_R32_SFLOAT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  EXPECT_NE(message(out).find("needs 3 channels"), std::string::npos) << message(out);
  in.image(Buffer::Color) = {fake, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
  EXPECT_NE(message(out).find("cannot be sampled"), std::string::npos) << message(out);
  in.image(Buffer::Color).layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  EXPECT_NE(message({fake, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_LAYOUT_GENERAL}).find("output image: format"), std::string::npos);
  EXPECT_NE(message({fake, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}).find("layout must be"),
            std::string::npos);
}

TEST(VulkanInterop, DenoiseVulkanRejectsACpuDenoiser) {
  auto cpu = Device::create({.backend = Backend::Cpu})->createDenoiser("accumulate");
  VulkanFrameInputs in{.width = 4, .height = 4};
  EXPECT_THROW(denoiseVulkan(*cpu, in, VulkanBufferView{}), Error);
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
