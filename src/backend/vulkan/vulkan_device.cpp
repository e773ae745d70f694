// The Vulkan rtd::Device: a vk::Context (owned, or on the application's device) from which
// every method's Vulkan denoiser is created.
#include "backend/vulkan/context.h"
#include "backend/vulkan/vulkan_denoiser.h"
#include "core/registry.h"
#include "core/stereo_pair.h"
#include "rtd/vulkan.h"

namespace rtd {

namespace {
class VulkanDevice final : public Device {
 public:
  explicit VulkanDevice(std::shared_ptr<vk::Context> ctx) : ctx_(std::move(ctx)) {}
  Backend backend() const override { return Backend::Vulkan; }
  std::string name() const override { return ctx_->name() + " (Vulkan)"; }
  std::unique_ptr<Denoiser> createDenoiser(std::string_view method) override {
    const MethodEntry* e = findMethod(method);
    if (!e) throw Error("unknown method '" + std::string(method) + "' (see `rtdenoise methods`)");
    if (!e->createVulkan)
      throw Error("method '" + std::string(method) + "' has no Vulkan implementation yet (use --backend cpu)");
    return e->createVulkan(*ctx_);
  }
  std::unique_ptr<StereoDenoiser> createStereoDenoiser(std::string_view method) override {
    const MethodEntry* e = findMethod(method);
    if (e && e->createStereoVulkan) return e->createStereoVulkan(*ctx_);
    return std::make_unique<StereoPair>(createDenoiser(method), createDenoiser(method));
  }

 private:
  std::shared_ptr<vk::Context> ctx_;  // shared with its denoisers, which may outlive the device
};
}  // namespace

std::unique_ptr<Device> createVulkanDevice(const DeviceDesc& desc) {
  return std::make_unique<VulkanDevice>(std::make_shared<vk::Context>(desc));
}

std::unique_ptr<Device> createVulkanDevice(const VulkanDeviceDesc& desc) {
  return std::make_unique<VulkanDevice>(std::make_shared<vk::Context>(desc));
}

void denoiseVulkan(Denoiser& denoiser, const VulkanFrameInputs& frame, const VulkanBufferView& output,
                   VkCommandBuffer commandBuffer) {
  auto* d = dynamic_cast<vk::VulkanDenoiserBase*>(&denoiser);
  if (!d) throw Error("denoiseVulkan: the denoiser was not created on a Vulkan device");
  d->denoiseGpu(frame, output, commandBuffer);
}

void denoiseVulkan(Denoiser& denoiser, const VulkanFrameInputs& frame, const VulkanImageView& output,
                   VkCommandBuffer commandBuffer) {
  auto* d = dynamic_cast<vk::VulkanDenoiserBase*>(&denoiser);
  if (!d) throw Error("denoiseVulkan: the denoiser was not created on a Vulkan device");
  d->denoiseGpu(frame, output, commandBuffer);
}

std::vector<DeviceInfo> listVulkanDevices() {
  std::vector<DeviceInfo> out;
  for (const auto& d : vk::enumeratePhysicalDevices()) {
    char version[32];
    std::snprintf(version, sizeof version, "Vulkan %u.%u.%u", VK_API_VERSION_MAJOR(d.apiVersion),
                  VK_API_VERSION_MINOR(d.apiVersion), VK_API_VERSION_PATCH(d.apiVersion));
    out.push_back({Backend::Vulkan, d.index, d.name, d.type + ", " + version + ", " + d.driver});
  }
  return out;
}

}  // namespace rtd
