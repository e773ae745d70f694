// An engine's side of Vulkan interop (docs/integration.md, "Recording into an engine's Vulkan
// command buffer"): the engine owns the instance, device, queue, G-buffer and command buffer;
// rtdenoise is created on that device and records its passes into the engine's command buffer
// between the engine's own commands (here: writing the G-buffer, and copying the result out).
// The G-buffer is in the engine's conventions: RGBA colour, motion in UV. The result is checked
// against the CPU backend on the same frames.
//   example_vulkan_record      (exit code 77: no Vulkan device and RTD_SKIP_VULKAN_TESTS=1)
#include <rtd/rtd.h>
#include <rtd/vulkan.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "common/scene.h"

#define VK_CHECK(call)                                                       \
  do {                                                                       \
    const VkResult r_ = (call);                                              \
    if (r_ != VK_SUCCESS) {                                                  \
      std::fprintf(stderr, "%s failed (VkResult %d)\n", #call, int(r_));     \
      std::exit(1);                                                          \
    }                                                                        \
  } while (0)

// What an engine already has: a Vulkan 1.2 device with a compute queue, and host-visible buffers.
struct Engine {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice gpu = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t family = 0;
  struct Buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    void* mapped;
  };
  std::vector<Buffer> buffers;

  bool create() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo ii{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ii.pApplicationInfo = &app;
    if (vkCreateInstance(&ii, nullptr, &instance) != VK_SUCCESS) return false;
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance, &n, nullptr);
    std::vector<VkPhysicalDevice> gpus(n);
    vkEnumeratePhysicalDevices(instance, &n, gpus.data());
    for (VkPhysicalDevice g : gpus) {
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(g, &p);
      if (p.apiVersion < VK_API_VERSION_1_2) continue;
      uint32_t nf = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(g, &nf, nullptr);
      std::vector<VkQueueFamilyProperties> families(nf);
      vkGetPhysicalDeviceQueueFamilyProperties(g, &nf, families.data());
      for (uint32_t f = 0; f < nf && !gpu; ++f)
        if (families[f].queueFlags & VK_QUEUE_COMPUTE_BIT) gpu = g, family = f;
      if (gpu) break;
    }
    if (!gpu) return false;
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    VK_CHECK(vkCreateDevice(gpu, &di, nullptr, &device));
    vkGetDeviceQueue(device, family, 0, &queue);
    return true;
  }

  // A storage buffer in host-visible, coherent memory, mapped (destroyed with the engine).
  Buffer buffer(VkDeviceSize bytes) {
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = bytes;
    bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    Buffer b{};
    VK_CHECK(vkCreateBuffer(device, &bi, nullptr, &b.buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, b.buffer, &req);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(gpu, &mp);
    const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = ~0u;
    for (uint32_t i = 0; i < mp.memoryTypeCount && ai.memoryTypeIndex == ~0u; ++i)
      if ((req.memoryTypeBits >> i & 1u) && (mp.memoryTypes[i].propertyFlags & want) == want) ai.memoryTypeIndex = i;
    VK_CHECK(vkAllocateMemory(device, &ai, nullptr, &b.memory));
    VK_CHECK(vkBindBufferMemory(device, b.buffer, b.memory, 0));
    VK_CHECK(vkMapMemory(device, b.memory, 0, bytes, 0, &b.mapped));
    buffers.push_back(b);
    return b;
  }

  ~Engine() {
    if (device) {
      vkDeviceWaitIdle(device);
      for (Buffer& b : buffers) {
        vkDestroyBuffer(device, b.buffer, nullptr);
        vkFreeMemory(device, b.memory, nullptr);
      }
      vkDestroyDevice(device, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
  }
};

int main() {
  const int w = kSceneWidth, h = kSceneHeight;
  Engine engine;
  if (!engine.create()) {
    const char* skip = std::getenv("RTD_SKIP_VULKAN_TESTS");
    std::fprintf(stderr, "no Vulkan 1.2 device with a compute queue\n");
    return skip && std::string(skip) == "1" ? 77 : 1;
  }
  {
    // rtdenoise on the engine's device; the denoisers must go before the engine's device does.
    auto device = rtd::createVulkanDevice({engine.instance, engine.gpu, engine.device, engine.queue, engine.family});
    auto denoiser = device->createDenoiser("svgf");
    auto reference = rtd::Device::create({.backend = rtd::Backend::Cpu})->createDenoiser("svgf");

    // The engine's G-buffer (RGBA colour, RGB albedo and normal, depth, UV motion) and output.
    const size_t pixels = size_t(w) * h;
    const Engine::Buffer gcolor = engine.buffer(pixels * 16);
    const Engine::Buffer galbedo = engine.buffer(pixels * 12);
    const Engine::Buffer gnormal = engine.buffer(pixels * 12);
    const Engine::Buffer gdepth = engine.buffer(pixels * 4);
    const Engine::Buffer gmotion = engine.buffer(pixels * 8);
    const Engine::Buffer result = engine.buffer(pixels * 16);    // rtdenoise's output, on the GPU
    const Engine::Buffer readback = engine.buffer(pixels * 16);  // where the engine copies it

    rtd::VulkanFrameInputs in{.width = w, .height = h};
    in[rtd::Buffer::Color] = {gcolor.buffer, 0, rtd::Format::Float4};
    in[rtd::Buffer::Albedo] = {galbedo.buffer, 0, rtd::Format::Float3};
    in[rtd::Buffer::Normal] = {gnormal.buffer, 0, rtd::Format::Float3};
    in[rtd::Buffer::Depth] = {gdepth.buffer, 0, rtd::Format::Float};
    in[rtd::Buffer::Motion] = {gmotion.buffer, 0, rtd::Format::Float2};
    in.conventions.motionUnits = rtd::FrameConventions::MotionUnits::Uv;  // the engine's motion is in UV
    const rtd::VulkanBufferView out{result.buffer, 0, rtd::Format::Float4};

    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = engine.family;
    VkCommandPool pool;
    VK_CHECK(vkCreateCommandPool(engine.device, &pi, nullptr, &pool));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd;
    VK_CHECK(vkAllocateCommandBuffers(engine.device, &ai, &cmd));
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    VK_CHECK(vkCreateFence(engine.device, &fi, nullptr, &fence));

    std::vector<float> color(pixels * 3), clean(pixels * 3), albedo(pixels * 3), normal(pixels * 3), depth(pixels),
        motion(pixels * 2), cpu(pixels * 4), gpu(pixels * 4);
    double worst = 0, peak = 0;
    for (int t = 0; t < kSceneFrames; ++t) {
      // The engine renders its G-buffer (here from the host, into its mapped buffers).
      sceneFrame(t, color.data(), clean.data(), albedo.data(), normal.data(), depth.data(), motion.data());
      float* rgba = static_cast<float*>(gcolor.mapped);
      for (size_t p = 0; p < pixels; ++p) {
        std::copy_n(&color[p * 3], 3, rgba + p * 4);
        rgba[p * 4 + 3] = 1.0f;
      }
      std::memcpy(galbedo.mapped, albedo.data(), pixels * 12);
      std::memcpy(gnormal.mapped, normal.data(), pixels * 12);
      std::memcpy(gdepth.mapped, depth.data(), pixels * 4);
      float* uv = static_cast<float*>(gmotion.mapped);
      for (size_t p = 0; p < pixels; ++p) uv[p * 2] = motion[p * 2] / float(w), uv[p * 2 + 1] = motion[p * 2 + 1] / float(h);

      // One command buffer: rtdenoise's passes, then the engine's copy of the result. rtdenoise
      // begins with a barrier after earlier writes and ends with one before later commands, so
      // the copy needs none of its own.
      VK_CHECK(vkResetCommandBuffer(cmd, 0));
      VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
      bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
      VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
      try {
        rtd::denoiseVulkan(*denoiser, in, out, cmd);
      } catch (const rtd::Error& e) {
        std::fprintf(stderr, "rtdenoise: %s\n", e.what());
        return 1;
      }
      const VkBufferCopy copy{0, 0, pixels * 16};
      vkCmdCopyBuffer(cmd, result.buffer, readback.buffer, 1, &copy);
      VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      toHost.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
      toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0,
                           nullptr);
      VK_CHECK(vkEndCommandBuffer(cmd));
      VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
      si.commandBufferCount = 1;
      si.pCommandBuffers = &cmd;
      VK_CHECK(vkQueueSubmit(engine.queue, 1, &si, fence));
      // A frame must complete before the denoiser's next frame is recorded (its history is reused).
      VK_CHECK(vkWaitForFences(engine.device, 1, &fence, VK_TRUE, UINT64_MAX));
      VK_CHECK(vkResetFences(engine.device, 1, &fence));
      std::memcpy(gpu.data(), readback.mapped, pixels * 16);

      // The same frame on the CPU, from host memory in the native conventions.
      rtd::FrameInputs host;
      host[rtd::Buffer::Color] = {color.data(), w, h, rtd::Format::Float3};
      host[rtd::Buffer::Albedo] = {albedo.data(), w, h, rtd::Format::Float3};
      host[rtd::Buffer::Normal] = {normal.data(), w, h, rtd::Format::Float3};
      host[rtd::Buffer::Depth] = {depth.data(), w, h, rtd::Format::Float};
      host[rtd::Buffer::Motion] = {motion.data(), w, h, rtd::Format::Float2};
      reference->denoise(host, {cpu.data(), w, h, rtd::Format::Float4});
      for (size_t k = 0; k < pixels * 4; ++k) {
        worst = std::max(worst, std::abs(double(gpu[k]) - cpu[k]));
        peak = std::max(peak, std::abs(double(cpu[k])));
      }
    }
    const double input = sceneRmse(color.data(), 3, clean.data()), output = sceneRmse(gpu.data(), 4, clean.data());
    std::printf("svgf on %s, recorded into the engine's command buffer: RMSE input %.4f, output %.4f; "
                "largest difference to the CPU %.2g (%.2g of the peak)\n",
                device->name().c_str(), input, output, worst, worst / peak);
    for (const auto& pass : denoiser->stats().passes) std::printf("  %-24s %8.3f ms\n", pass.name.c_str(), pass.milliseconds);
    vkDestroyFence(engine.device, fence, nullptr);
    vkDestroyCommandPool(engine.device, pool, nullptr);
    // The backends agree within 1e-4 of the peak for SVGF (docs/vulkan.md).
    if (!(output < 0.5 * input && worst <= 1e-4 * peak)) return 1;
  }
  return 0;
}
