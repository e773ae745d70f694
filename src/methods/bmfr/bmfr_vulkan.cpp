// Method "bmfr" on the Vulkan backend: the passes of bmfr.cpp, pass for pass, as compute
// shaders (the shared ones of src/backend/vulkan and BMFR's own in shaders/ here). Phase II runs
// one workgroup per block (bmfr_fit.comp); docs/vulkan.md and docs/methods/bmfr.md ("On Vulkan")
// describe the layout and the agreement with the CPU.
#if defined(RTD_HAS_VULKAN)
#include <algorithm>
#include <cstddef>
#include <utility>

#include "backend/vulkan/vulkan_denoiser.h"
#include "methods/bmfr/blocks.h"
#include "methods/bmfr/bmfr_common.h"
#include "methods/bmfr/qr.h"
#include "rtd/methods/bmfr.h"

namespace rtd {

namespace {

constexpr uint32_t kFitStride = 64;       // floats per block in the fit buffer (shaders/bmfr.glsl)
constexpr uint32_t kFitWorkgroup = 256;   // bmfr_fit.comp's local size
constexpr int kMaxColumns = bmfr::kMaxFeatures + bmfr::kMaxChannels;
// The fit's block matrices share one device buffer; above this size (or the device's
// maxStorageBufferRange) the blocks are fitted in several dispatches that reuse it.
constexpr VkDeviceSize kMaxScratchBytes = VkDeviceSize(128) << 20;

// Feature codes of bmfr.glsl: kind in bits 4-7, channel in bits 0-3, four per word.
void packFeatures(const std::vector<bmfr::Feature>& features, uint32_t codes[4]) {
  std::fill(codes, codes + 4, 0u);
  for (size_t k = 0; k < features.size(); ++k) {
    const uint32_t code = (uint32_t(features[k].kind) << 4) | uint32_t(features[k].channel);
    codes[k / 4] |= code << ((k % 4) * 8);
  }
}

class BmfrVulkan final : public vk::VulkanDenoiser<BmfrSettings> {
 public:
  using VulkanDenoiser::VulkanDenoiser;
  std::vector<Buffer> requiredBuffers() const override { return bmfr::requiredBuffers(settings_); }

 protected:
  std::vector<Buffer> extraBuffers() const override { return bmfr::optionalBuffers(settings_); }

  void resizeHistory(int w, int h) override {
    demodulated_.allocate(ctx_, w, h, 3);
    reprojection_.allocate(ctx_, w, h, 8);
    noisy_.resize(ctx_, w, h, false);  // no moments: R, G, B, length
    for (auto& f : filtered_) f.allocate(ctx_, w, h, 3);
    fitted_.allocate(ctx_, w, h, 3);
    remodulated_.allocate(ctx_, w, h, 3);
    taa_.resize(w, h);
    // The 32x32 grid has the most blocks; the fit buffer holds every block of it.
    const int blocks32 = bmfr::makeBlockGrid(w, h, 32, 0, true).count();
    const int blocks64 = bmfr::makeBlockGrid(w, h, 64, 0, true).count();
    fits_ = vk::DeviceBuffer(ctx_, VkDeviceSize(blocks32) * kFitStride * 4, false);
    // Scratch for the largest block matrices any setting can ask for (15 columns, every pixel
    // of a 32 or 64 block), capped: larger frames fit their blocks in several dispatches.
    const VkDeviceSize largest = std::max(VkDeviceSize(blocks32) * blockBytes(kMaxColumns, 32 * 32),
                                          VkDeviceSize(blocks64) * blockBytes(kMaxColumns, 64 * 64));
    scratch_ = vk::DeviceBuffer(ctx_, std::min(largest, scratchLimit()), false);
  }

  void resetHistory() override {
    noisy_.reset();
    taa_.reset();
    frameIndex_ = 0;
  }

  const vk::Planes& process(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous) override {
    const BmfrSettings& s = settings_;
    const vk::Planes* albedo = s.demodulate && frame.has(Buffer::Albedo) ? &frame[Buffer::Albedo] : nullptr;
    const int prev = cur_;
    cur_ ^= 1;
    rec.pass("demodulate");
    vk::demodulate(rec, frame[Buffer::Color], albedo, demodulated_);
    rec.pass("reproject");
    vk::reproject(rec, frame, previous, s.reprojection, reprojection_);
    // Phase I: cumulative then exponential average, w = max(1/n, 0.2) (Sec. 4.1), 8-bit counts.
    rec.pass("accumulateNoisy");
    noisy_.run(rec, reprojection_, demodulated_, s.alphaNoisy, s.alphaNoisy, s.maxHistoryLength);
    const vk::Planes* fitted = &noisy_.current();
    if (s.fit) {
      fitAndSynthesize(rec, frame);
      fitted = &fitted_;
    }
    const vk::Planes* filtered = fitted;
    if (s.accumulateFiltered) {
      // Phase III: the same taps and sample counts as phase I, w = max(1/n, 0.1) (Sec. 4.3).
      rec.pass("accumulateFiltered");
      struct PC {
        uint32_t width, height;
        float alpha;
      } pc{uint32_t(frame.width), uint32_t(frame.height), s.alphaFiltered};
      rec.dispatch("bmfr_accumulate", {reprojection_, noisy_.current(), *fitted, filtered_[prev], filtered_[cur_]}, pc,
                   frame.width, frame.height);
      filtered = &filtered_[cur_];
    }
    rec.pass("remodulate");
    vk::remodulate(rec, *filtered, albedo, remodulated_);
    ++frameIndex_;
    if (!s.taa.taa) return remodulated_;
    rec.pass("taa");
    // The own-surface box's keys (as bmfr_simd.cpp): object id and the emitters the fits leave out.
    const bool keyed = s.taa.taaOwnSurface && vk::taaSurfaceKeys(rec, frame, &s.emitters, nullptr, taaKeys_);
    return taa_.run(rec, reprojection_, remodulated_, s.taa, keyed ? &taaKeys_ : nullptr);
  }

 private:
  // Bytes of one block matrix in the scratch buffer: columns x rows floats, rounded up so every
  // dispatch's binding offset meets minStorageBufferOffsetAlignment (at most 256 bytes).
  static VkDeviceSize blockBytes(int columns, int rows) {
    return (VkDeviceSize(columns) * VkDeviceSize(rows) * 4 + 255) / 256 * 256;
  }
  VkDeviceSize scratchLimit() const {
    return std::min<VkDeviceSize>(kMaxScratchBytes, ctx_.limits().maxStorageBufferRange) / 256 * 256;
  }

  void fitAndSynthesize(vk::Recorder& rec, const vk::GpuFrame& frame) {
    const BmfrSettings& s = settings_;
    bmfr::selectFeatures(s, [&](Buffer b) { return frame.has(b); }, features_);
    const int size = s.blockSize == BmfrBlockSize::Block64 ? 64 : 32;
    const bmfr::BlockGrid grid = bmfr::makeBlockGrid(frame.width, frame.height, size, frameIndex_, s.blockOffsets);
    const int rows = bmfr::rowsPerBlock(size, s.samplesPerBlock);
    const int m = int(features_.size());
    uint32_t codes[4];
    packFeatures(features_, codes);
    const vk::Binding normals = frame.bindingOf(Buffer::Normal, ctx_), positions = frame.bindingOf(Buffer::Position, ctx_);
    const vk::Binding ids = frame.bindingOf(Buffer::MaterialId, ctx_), roughness = frame.bindingOf(Buffer::Roughness, ctx_);
    // Issue 12: emitter rows weigh 0 in the fits, emitter pixels keep their phase I value.
    const uint32_t excludeEmitters = s.emitters.excludeEmitters && frame.has(Buffer::Emission);
    const vk::Binding emission = frame.bindingOf(Buffer::Emission, ctx_);

    rec.pass("fit");
    struct FitPC {
      uint32_t width, height;
      int32_t originX, originY;
      uint32_t blocksX, size, rows, features, blockBase, blockStride, frameIndex;
      float noise;
      uint32_t codes[4];
      float emitterThreshold;
      uint32_t excludeEmitters;
    } pc{uint32_t(frame.width), uint32_t(frame.height), grid.originX, grid.originY, uint32_t(grid.blocksX),
         uint32_t(size), uint32_t(rows), uint32_t(m), 0, 0, uint32_t(frameIndex_),
         s.noiseAmount > 0.0f ? bmfr::noiseAmplitude(s.noiseAmount, rows) : 0.0f, {codes[0], codes[1], codes[2], codes[3]},
         s.emitters.emitterThreshold, excludeEmitters};
    static_assert(offsetof(FitPC, codes) == 48, "uvec4 codes sits at offset 48 in bmfr_fit.comp");
    const VkDeviceSize bytes = blockBytes(m + 3, rows);
    pc.blockStride = uint32_t(bytes / 4);
    const int chunk = int(std::max<VkDeviceSize>(1, scratch_.size() / bytes));
    for (int first = 0; first < grid.count(); first += chunk) {
      const int n = std::min(chunk, grid.count() - first);
      pc.blockBase = uint32_t(first);
      rec.dispatch("bmfr_fit",
                   {noisy_.current(), normals, positions, ids, roughness,
                    vk::Binding(scratch_.handle(), 0, VkDeviceSize(n) * bytes), fits_, emission},
                   pc, n * int(kFitWorkgroup), 1);
    }

    // Eq. 6: y = T alpha per pixel with its block's weights and normalization, clamped >= 0.
    rec.pass("synthesize");
    struct SynthesisPC {
      uint32_t width, height;
      int32_t originX, originY;
      uint32_t blocksX, size, features, pad;
      uint32_t codes[4];
      float emitterThreshold;
      uint32_t excludeEmitters;
    } spc{uint32_t(frame.width), uint32_t(frame.height), grid.originX, grid.originY, uint32_t(grid.blocksX),
          uint32_t(size), uint32_t(m), 0, {codes[0], codes[1], codes[2], codes[3]},
          s.emitters.emitterThreshold, excludeEmitters};
    rec.dispatch("bmfr_synthesize", {fits_, normals, positions, ids, roughness, fitted_, emission, noisy_.current()}, spc,
                 frame.width, frame.height);
  }

  vk::Planes demodulated_, reprojection_, fitted_, remodulated_;
  vk::GpuTemporalAccumulator noisy_;  // phase I history: colour (planes 0-2) and sample count (plane 3)
  vk::Planes filtered_[2];            // phase III history
  int cur_ = 0;
  int frameIndex_ = 0;
  vk::DeviceBuffer fits_, scratch_;
  std::vector<bmfr::Feature> features_;
  vk::GpuTaa taa_;
  vk::Planes taaKeys_;  // TaaSettings::taaOwnSurface
};

}  // namespace

std::unique_ptr<Denoiser> createBmfrVulkan(vk::Context& ctx) { return std::make_unique<BmfrVulkan>(ctx); }

}  // namespace rtd
#endif
