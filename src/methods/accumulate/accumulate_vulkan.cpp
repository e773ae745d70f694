// Method "accumulate" on the Vulkan backend: the same passes as accumulate.cpp, recorded as
// compute dispatches of the shared GPU passes (src/backend/vulkan/passes.h).
#ifdef RTD_HAS_VULKAN
#include "backend/vulkan/vulkan_denoiser.h"
#include "rtd/methods/accumulate.h"

namespace rtd {

namespace {
class AccumulateVulkan final : public vk::VulkanDenoiser<AccumulateSettings> {
 public:
  using VulkanDenoiser::VulkanDenoiser;
  std::vector<Buffer> requiredBuffers() const override { return {Buffer::Color}; }

 protected:
  void resizeHistory(int w, int h) override {
    demodulated_.allocate(ctx_, w, h, 3);
    reprojection_.allocate(ctx_, w, h, 8);
    accumulator_.resize(ctx_, w, h);
    output_.allocate(ctx_, w, h, 3);
  }
  void resetHistory() override { accumulator_.reset(); }

  const vk::Planes& process(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous) override {
    const vk::Planes* albedo = settings_.demodulate && frame.has(Buffer::Albedo) ? &frame[Buffer::Albedo] : nullptr;
    rec.pass("demodulate");
    vk::demodulate(rec, frame[Buffer::Color], albedo, demodulated_);
    rec.pass("reproject");
    vk::reproject(rec, frame, previous, settings_.reprojection, reprojection_);
    rec.pass("accumulate");
    accumulator_.run(rec, reprojection_, demodulated_, settings_.alpha, settings_.alpha, settings_.maxHistoryLength);
    rec.pass("remodulate");
    vk::remodulate(rec, accumulator_.current(), albedo, output_);
    return output_;
  }

 private:
  vk::Planes demodulated_, reprojection_, output_;
  vk::GpuTemporalAccumulator accumulator_;
};
}  // namespace

std::unique_ptr<Denoiser> createAccumulateVulkan(vk::Context& ctx) { return std::make_unique<AccumulateVulkan>(ctx); }

}  // namespace rtd
#endif
