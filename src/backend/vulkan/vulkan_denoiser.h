// Base of every Vulkan denoiser (the twin of CpuDenoiser): validates and imports the frame
// (host memory through a staging buffer, or the application's VkBuffers), keeps the current and
// previous frame on the GPU, records the method's passes, exports the result and turns the
// timestamp queries into per-pass GPU times. A method implements process().
#pragma once
#include <vulkan/vulkan.h>

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "backend/vulkan/context.h"
#include "backend/vulkan/passes.h"
#include "core/conventions.h"
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
  /// A wrapper's passes around the method, in one submission on the denoiser's own command
  /// buffer, waited for: `before` is recorded after the opening barrier and before the import
  /// (it may write the buffers `frame` views), `after` after the export (it may read `output`).
  /// Each starts its passes with rec.pass(), so stats() are this frame's and hold them
  /// (guide-ray supersampling, backend/vulkan/guide_rays_vulkan.cpp).
  void denoiseGpuAround(const VulkanFrameInputs& frame, const VulkanBufferView& output,
                        const std::function<void(Recorder&)>& before, const std::function<void(Recorder&)>& after);
  Context& context() const { return ctx_; }

  /// Two views (the eyes of a two-view method, rtd/stereo.h), one denoiser each, recorded into
  /// one command buffer from host memory: a's and b's processFront(), then `exchange` (through
  /// a's recorder, as pass "eyeReprojection"), then each processBack() and export. Each view's
  /// stats() hold its passes; "(other eye)" marks the time its recording waited for the other.
  static void denoiseTwoViews(VulkanDenoiserBase& a, VulkanDenoiserBase& b, const FrameInputs& inA,
                              const FrameInputs& inB, const ImageView& outA, const ImageView& outB,
                              const std::function<void(Recorder&)>& exchange);

 protected:
  /// Buffers imported when the frame has them (importedBuffers(), as on the CPU).
  std::vector<Buffer> usedBuffers(bool frameHasMotion) const;
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
  /// Two-view methods split process() around the exchange between the views (denoiseTwoViews):
  /// the passes before it, and the rest returning the planes to export.
  virtual void processFront(Recorder&, const GpuFrame&, const GpuFrame*) {}
  virtual const Planes& processBack(Recorder& rec, const GpuFrame& frame, const GpuFrame* previous) {
    return process(rec, frame, previous);
  }
  /// The frame being recorded (between the import and the export).
  const GpuFrame& recordingFrame() const { return frames_[cur_]; }

  /// FrameStats::memory: "frames" (the current and previous frame's imported planes and
  /// cameras), the method's own categories (methodMemory()), "planes" (the rest of the
  /// device-local memory the denoiser holds) and "staging" (its host-visible buffers: upload,
  /// read-back, counters). Together they are every DeviceBuffer created on its behalf.
  std::vector<MemoryUse> memoryUse() const;
  /// Categories that part the method's device-local planes further (Gersthofer's "history"
  /// and "intermediate"); "planes" keeps what they leave.
  virtual std::vector<MemoryUse> methodMemory() const { return {}; }
  /// The tally of this denoiser's device memory. The public entry points open its
  /// MemoryOwnerScope; a derived constructor or settingsChanged() that allocates opens it too.
  const std::shared_ptr<MemoryTally>& memoryOwner() const { return memoryOwner_; }

  // Keeps the device alive while a denoiser exists, even after its rtd::Device is gone (as
  // CPU denoisers keep their arena); null for a Context not owned by a shared_ptr (tests).
  std::shared_ptr<Context> keepAlive_;
  Context& ctx_;
  int width_ = 0, height_ = 0;
  /// FrameStats::notes of the frame process() recorded (parts that did not run, and why).
  std::vector<std::string> notes_;
  /// Set by a process() whose result already holds the separated emission (a tone map must
  /// see it), so that the export does not add it again (as CpuDenoiser).
  bool resultHasEmission_ = false;

 private:
  /// Where the pixels come from and go to: a buffer with strides, or an image (`shader` then
  /// names the import_image_* / export_image_* pass that reads or writes its format).
  struct Import {
    Buffer which;
    Binding source;
    uint32_t offsetWords, pixelStrideWords, rowStrideWords;  // 16-bit units for halves
    uint32_t type;  // import.comp's: 0 float, 1 int32, 2 half
    const char* imageShader = nullptr;
  };
  struct Export {
    Binding target;
    uint32_t offsetWords, pixelStrideWords, rowStrideWords, channels;
    const char* imageShader = nullptr;
  };
  void denoiseHost(const FrameInputs& frame, const ImageView& output);
  /// A host-memory frame staged for recording (denoiseHost()'s first half): validated,
  /// uploaded, history prepared, the read-back buffer ready.
  struct HostFrame {
    std::vector<Import> imports;
    Export out;
    Camera camera;
    ConventionTransform conventions;
    int width = 0, height = 0;
    uint32_t outChannels = 3;
    FrameStats stats;
    std::chrono::steady_clock::time_point start;
  };
  HostFrame stageHost(const FrameInputs& in, const ImageView& output);
  /// denoiseHost()'s second half once the commands ran: timings, read-back, counts, stats().
  void finishHost(HostFrame& frame, const ImageView& output);
  void denoiseIntoBuffer(const VulkanFrameInputs& frame, const VulkanBufferView& output, VkCommandBuffer cmd);
  void denoiseIntoImage(const VulkanFrameInputs& frame, const VulkanImageView& output, VkCommandBuffer cmd);
  void denoiseGpu(const VulkanFrameInputs& frame, const Export& out, VkCommandBuffer cmd);
  void bindBufferView(const VulkanBufferView& v, const std::string& what, uint32_t channels, int w, int h,
                      Binding& binding, uint32_t& offsetUnits, uint32_t& pixelUnits, uint32_t& rowUnits) const;
  void prepare(int w, int h, bool cameraCut);
  void record(VkCommandBuffer cmd, const std::vector<Import>& imports, const Camera& camera,
              const ConventionTransform& conventions, const Export& out);
  /// record() in two steps around the method's passes: the import, and the export.
  Recorder beginRecord(VkCommandBuffer cmd, const std::vector<Import>& imports, const Camera& camera,
                       const ConventionTransform& conventions, const Export& out);
  void endRecord(Recorder& rec, const Planes& result, const Export& out);
  void submitAndWait();
  /// The sanitize counters of the last frame that ran into `stats` (sanitized, sanitizedValues).
  void readSanitizeCounts(FrameStats& stats) const;
  /// GPU pass times of the last recorded frame into `stats`; false if not available yet.
  bool readTimings(FrameStats& stats, bool wait);

  std::shared_ptr<MemoryTally> memoryOwner_ = std::make_shared<MemoryTally>();  // memoryOwner()
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
  // denoiseGpuAround()'s passes while it records, else null.
  const std::function<void(Recorder&)>* before_ = nullptr;
  const std::function<void(Recorder&)>* after_ = nullptr;
};

/// A Vulkan denoiser of method S: settings by name and by type, as on the CPU.
template <class S> class VulkanDenoiser : public TypedSettings<S, VulkanDenoiserBase> {
 public:
  using TypedSettings<S, VulkanDenoiserBase>::TypedSettings;

 protected:
  const ReprojectionSettings& reprojectionSettings() const override { return this->settings_.reprojection; }
};

}  // namespace rtd::vk
