// Base of every Vulkan denoiser (the twin of CpuDenoiser): validates and imports the frame
// (host memory through a staging buffer, or the application's VkBuffers), keeps the current and
// previous frame on the GPU, records the method's passes, exports the result and turns the
// timestamp queries into per-pass GPU times. A method implements process().
#pragma once
#include <vulkan/vulkan.h>

#include <string>
#include <vector>

#include "backend/vulkan/context.h"
#include "backend/vulkan/passes.h"
#include "core/settings_reflect.h"
#include "rtd/denoiser.h"
#include "rtd/vulkan.h"

namespace rtd::vk {

class VulkanDenoiserBase : public Denoiser {
 public:
  explicit VulkanDenoiserBase(Context& ctx);
  ~VulkanDenoiserBase() override;

  Backend backend() const override { return Backend::Vulkan; }
  const FrameStats& stats() const override { return stats_; }
  void reset() override {
    hasPrevious_ = false;
    resetHistory();
  }
  void denoise(const FrameInputs& frame, const ImageView& output) final;
  /// rtd::denoiseVulkan (rtd/vulkan.h): into a VkBuffer range or a storage image.
  void denoiseGpu(const VulkanFrameInputs& frame, const VulkanBufferView& output, VkCommandBuffer cmd);
  void denoiseGpu(const VulkanFrameInputs& frame, const VulkanImageView& output, VkCommandBuffer cmd);

 protected:
  /// Buffers imported when the frame has them (importedBuffers(), as on the CPU).
  std::vector<Buffer> usedBuffers() const;
  /// Buffers the method reads beyond its required ones and the shared passes'.
  virtual std::vector<Buffer> extraBuffers() const { return {}; }
  /// The method's reprojection settings (which guides the shared passes read).
  virtual const ReprojectionSettings& reprojectionSettings() const = 0;
  /// (Re)allocate history for a new size (the GPU is idle); called before the first frame.
  virtual void resizeHistory(int width, int height) = 0;
  /// Forget history (allocations stay).
  virtual void resetHistory() = 0;
  /// Record the method's passes (rec.pass("name") before each) for `frame`; `previous` is the
  /// last frame or null after a reset. Returns the planes (RGB) to export.
  virtual const Planes& process(Recorder& rec, const GpuFrame& frame, const GpuFrame* previous) = 0;

  // Keeps the device alive while a denoiser exists, even after its rtd::Device is gone (as
  // CPU denoisers keep their arena); null for a Context not owned by a shared_ptr (tests).
  std::shared_ptr<Context> keepAlive_;
  Context& ctx_;
  int width_ = 0, height_ = 0;
  /// Set by a process() whose result already holds the separated emission (a tone map must
  /// see it), so that the export does not add it again (as CpuDenoiser).
  bool resultHasEmission_ = false;

 private:
  /// Where the pixels come from and go to: a buffer with strides, or an image (`shader` then
  /// names the import_image_* / export_image_* pass that reads or writes its format).
  struct Import {
    Buffer which;
    Binding source;
    uint32_t offsetWords, pixelStrideWords, rowStrideWords;
    bool isInt;
    const char* imageShader = nullptr;
  };
  struct Export {
    Binding target;
    uint32_t offsetWords, pixelStrideWords, rowStrideWords, channels;
    const char* imageShader = nullptr;
  };
  void denoiseGpu(const VulkanFrameInputs& frame, const Export& out, VkCommandBuffer cmd);
  void bindBufferView(const VulkanBufferView& v, const std::string& what, uint32_t channels, int w, int h,
                      Binding& binding, uint32_t& offsetWords, uint32_t& pixelWords, uint32_t& rowWords) const;
  void prepare(int w, int h, bool cameraCut);
  void record(VkCommandBuffer cmd, const std::vector<Import>& imports, const Camera& camera, const Export& out);
  void submitAndWait();
  /// The sanitize counters of the last frame that ran into `stats` (sanitized, sanitizedValues).
  void readSanitizeCounts(FrameStats& stats) const;
  /// GPU pass times of the last recorded frame into `stats`; false if not available yet.
  bool readTimings(FrameStats& stats, bool wait);

  DescriptorCache descriptors_;
  GpuFrame frames_[2];
  int cur_ = 0;
  bool hasPrevious_ = false;
  DeviceBuffer upload_, readback_, counter_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  std::vector<std::string> recordedPasses_;
  uint32_t recordedQueries_ = 0;
  FrameStats stats_;
};

/// A Vulkan denoiser of method S: settings by name and by type, as on the CPU.
template <class S> class VulkanDenoiser : public TypedSettings<S, VulkanDenoiserBase> {
 public:
  using TypedSettings<S, VulkanDenoiserBase>::TypedSettings;

 protected:
  const ReprojectionSettings& reprojectionSettings() const override { return this->settings_.reprojection; }
};

}  // namespace rtd::vk
