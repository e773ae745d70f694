// Method "tnnd" on the Vulkan backend: the passes of tnnd.cpp as compute shaders
// (shaders/tnnd_encode.comp, tnnd_step.comp once per iteration, tnnd_decode.comp), with the
// shared reprojection and accumulation in front when "accumulate" is on. The 360 weights live
// in a small host-visible buffer, rewritten when the "weights" setting changes.
#if defined(RTD_HAS_VULKAN)
#include <algorithm>
#include <cstring>

#include "backend/vulkan/vulkan_denoiser.h"
#include "core/conventions.h"
#include "methods/tnnd/tnnd_model.h"
#include "rtd/methods/tnnd.h"

namespace rtd {

namespace {

class TnndVulkan final : public vk::VulkanDenoiser<TnndSettings> {
 public:
  explicit TnndVulkan(vk::Context& ctx) : VulkanDenoiser(ctx) {
    const vk::MemoryOwnerScope owner(memoryOwner());
    weightsBuffer_ = vk::DeviceBuffer(ctx, tnnd::kParameters * sizeof(float), true);
    upload(tnnd::loadWeights(""));
  }
  std::vector<Buffer> requiredBuffers() const override { return {Buffer::Color, Buffer::Normal, Buffer::Albedo}; }

 protected:
  void settingsChanged() override {
    if (settings_.weights == loaded_) return;
    try {
      upload(tnnd::loadWeights(settings_.weights));
      loaded_ = settings_.weights;
    } catch (...) {
      settings_.weights = loaded_;  // the setting keeps naming the weights in use
      throw;
    }
  }
  void resizeHistory(int w, int h) override {
    reprojection_.allocate(ctx_, w, h, 8);
    accumulator_.resize(ctx_, w, h);
    for (auto& s : state_) s.allocate(ctx_, w, h, tnnd::kState);
    output_.allocate(ctx_, w, h, 3);
  }
  void resetHistory() override { accumulator_.reset(); }

  const vk::Planes& process(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous) override {
    const TnndSettings& s = settings_;
    const vk::Planes* color = &frame[Buffer::Color];
    if (s.accumulate) {
      rec.pass("reproject");
      vk::reproject(rec, frame, previous, s.reprojection, reprojection_);
      rec.pass("accumulate");
      accumulator_.run(rec, reprojection_, frame[Buffer::Color], s.alpha, s.alpha, s.maxHistoryLength);
      color = &accumulator_.current();
    }
    const uint32_t w = uint32_t(frame.width), h = uint32_t(frame.height);
    rec.pass("encode");
    struct EncodePC {
      uint32_t width, height;
      float r[9];
    } epc{w, h, {}};
    const std::array<float, 9> r = worldToViewRotation(frame.cameraValue);
    std::copy(r.begin(), r.end(), epc.r);
    rec.dispatch("tnnd_encode", {*color, frame[Buffer::Normal], frame[Buffer::Albedo], state_[0]}, epc, frame.width,
                 frame.height);
    struct SizePC {
      uint32_t width, height;
    } pc{w, h};
    int cur = 0;
    for (int i = 0; i < s.iterations; ++i) {
      rec.pass("step" + std::to_string(i + 1));
      rec.dispatch("tnnd_step", {weightsBuffer_, state_[cur], state_[cur ^ 1]}, pc, frame.width, frame.height);
      cur ^= 1;
    }
    rec.pass("decode");
    rec.dispatch("tnnd_decode", {state_[cur], output_}, pc, frame.width, frame.height);
    return output_;
  }

 private:
  void upload(const tnnd::Weights& wt) {
    float* dst = static_cast<float*>(weightsBuffer_.mapped());
    std::memcpy(dst, wt.w.data(), wt.w.size() * sizeof(float));
    std::memcpy(dst + wt.w.size(), wt.b.data(), wt.b.size() * sizeof(float));
  }

  vk::DeviceBuffer weightsBuffer_;
  std::string loaded_;
  vk::Planes reprojection_, state_[2], output_;
  vk::GpuTemporalAccumulator accumulator_;
};

}  // namespace

std::unique_ptr<Denoiser> createTnndVulkan(vk::Context& ctx) { return std::make_unique<TnndVulkan>(ctx); }

}  // namespace rtd
#endif
