// rtdenoise — Vulkan interop: run the denoisers on the application's own Vulkan device and
// pass GPU-resident buffers or images, so an engine keeps its frame on the GPU. Only this header needs
// <vulkan/vulkan.h>; see docs/vulkan.md.
//
//   auto device = rtd::createVulkanDevice({instance, physicalDevice, vkDevice, queue, family});
//   auto denoiser = device->createDenoiser("svgf");
//   rtd::VulkanFrameInputs in{.width = w, .height = h};
//   in[rtd::Buffer::Color] = {colorBuffer, 0, rtd::Format::Float4};
//   ...
//   rtd::denoiseVulkan(*denoiser, in, {outputBuffer, 0, rtd::Format::Float4}, commandBuffer);
#pragma once
#include <vulkan/vulkan.h>

#include <array>
#include <memory>

#include "rtd/denoiser.h"

namespace rtd {

/// The application's device. rtdenoise creates its pipelines, buffers and query pools on
/// `device` and submits (when it submits at all) on `queue`, which must belong to
/// `queueFamily` and support compute. Vulkan 1.2; no extension or optional feature is needed.
/// The handles must outlive the rtd::Device and its denoisers.
struct VulkanDeviceDesc {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queueFamily = 0;
};

/// A Vulkan rtd::Device on the application's device. Throws rtd::Error on a bad handle set.
std::unique_ptr<Device> createVulkanDevice(const VulkanDeviceDesc& desc);

/// Pixels in one of the application's VkBuffers (created with VK_BUFFER_USAGE_STORAGE_BUFFER_BIT
/// on the same device). Pixel (x, y), channel c, is the 32-bit value (16-bit for Half*) at byte
/// offset + y * rowStride + x * pixelStride + channelBytes(format) * c; rows from the top.
/// Strides 0 mean tightly packed. `offset` and the strides must be multiples of the channel size
/// (4 bytes, 2 for Half*). Formats as in rtd::ImageView; outputs are Float3 or Float4.
struct VulkanBufferView {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  Format format = Format::Undefined;
  uint32_t pixelStride = 0;
  uint32_t rowStride = 0;
  bool empty() const { return buffer == VK_NULL_HANDLE; }
};

/// One of the application's images (an engine's G-buffer target or its output image), through
/// a 2D VkImageView of it on the same device: texel (x, y) of the view's first mip level and
/// array layer is pixel (x, y), rows from the top; the view covers at least width x height.
///
/// Inputs are read with texelFetch as sampled images: the image needs
/// VK_IMAGE_USAGE_SAMPLED_BIT, and `layout` (the layout it is in while rtdenoise's commands run;
/// rtdenoise does not transition it) must be valid for a sampled image:
/// VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL or
/// VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL. Supported input formats (sampled images of these
/// formats are mandatory in Vulkan, so every device reads them): R32G32B32A32_SFLOAT,
/// R16G16B16A16_SFLOAT, R32G32_SFLOAT, R16G16_SFLOAT, R32_SFLOAT, R16_SFLOAT,
/// R8G8B8A8_UNORM, R16G16B16A16_UNORM, A2B10G10R10_UNORM_PACK32, B10G11R11_UFLOAT_PACK32
/// (channels beyond the buffer's are ignored), and R32_SINT / R32_UINT for ids.
///
/// The output is written as a storage image: VK_IMAGE_USAGE_STORAGE_BIT, layout
/// VK_IMAGE_LAYOUT_GENERAL, format R32G32B32A32_SFLOAT or R16G16B16A16_SFLOAT (alpha = 1).
struct VulkanImageView {
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  bool empty() const { return view == VK_NULL_HANDLE; }
};

/// One frame whose buffers live on the GPU (the twin of rtd::FrameInputs). Each buffer is given
/// either as a VkBuffer range (`buffers`) or as an image (`images`); an image wins where both are set.
struct VulkanFrameInputs {
  int width = 0;
  int height = 0;
  std::array<VulkanBufferView, kBufferCount> buffers{};
  std::array<VulkanImageView, kBufferCount> images{};
  Camera camera;
  /// How the buffers differ from the native conventions (rtd::FrameConventions; converted on the GPU).
  FrameConventions conventions;
  bool cameraCut = false;

  VulkanBufferView& operator[](Buffer b) { return buffers[int(b)]; }
  const VulkanBufferView& operator[](Buffer b) const { return buffers[int(b)]; }
  VulkanImageView& image(Buffer b) { return images[int(b)]; }
  const VulkanImageView& image(Buffer b) const { return images[int(b)]; }
  bool has(Buffer b) const { return !buffers[int(b)].empty() || !images[int(b)].empty(); }
};

/// Denoises a GPU-resident frame into `output` (Float3 or Float4) with a denoiser created on a
/// Vulkan device. With `commandBuffer` (recording, from a pool of the device's queue family) the
/// work is recorded there and the application submits it: rtdenoise starts with a barrier that
/// makes all earlier writes visible to its reads and ends with one that makes its writes visible
/// to all later commands; denoiser.stats() then report the latest frame whose GPU timestamps are
/// available. Without it, rtdenoise submits on the device's queue and waits. Throws rtd::Error
/// for a denoiser of another backend or bad views.
void denoiseVulkan(Denoiser& denoiser, const VulkanFrameInputs& frame, const VulkanBufferView& output,
                   VkCommandBuffer commandBuffer = VK_NULL_HANDLE);
/// The same, writing the result into the application's storage image (see VulkanImageView).
void denoiseVulkan(Denoiser& denoiser, const VulkanFrameInputs& frame, const VulkanImageView& output,
                   VkCommandBuffer commandBuffer = VK_NULL_HANDLE);

}  // namespace rtd
