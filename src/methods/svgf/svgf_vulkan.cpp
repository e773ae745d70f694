// Method "svgf" on the Vulkan backend: the passes of svgf.cpp, pass for pass, as compute
// shaders (shared ones in src/backend/vulkan/shaders, SVGF's own in shaders/ here). Every
// setting of SvgfSettings is honoured, variants and the progressive sub-1-spp mode included.
#if defined(RTD_HAS_VULKAN) && __has_include("rtd/methods/svgf.h")
#include <algorithm>
#include <cmath>

#include "backend/vulkan/vulkan_denoiser.h"
#include "methods/svgf/svgf_passes.h"
#include "methods/svgf/svgf_reflections_vulkan.h"
#include "rtd/methods/svgf.h"

namespace rtd {

namespace {

constexpr int kMaxStreams = 2;

uint32_t luminanceMode(SvgfLuminance l) {
  switch (l) {
    case SvgfLuminance::rec601: return 1;
    case SvgfLuminance::cieLightness: return 2;
    default: return 0;
  }
}

// One radiance stream and its history, as in svgf.cpp.
struct GpuStream {
  svgf::StreamPlan plan{Buffer::Color, "color", true, false};  // which buffer, and how it is filtered
  vk::Planes demod;
  vk::GpuTemporalAccumulator accumulator;
};

class SvgfVulkan final : public vk::VulkanDenoiser<SvgfSettings> {
 public:
  using VulkanDenoiser::VulkanDenoiser;
  std::vector<Buffer> requiredBuffers() const override { return {Buffer::Color, Buffer::Normal, Buffer::Depth}; }

 protected:
  std::vector<Buffer> extraBuffers() const override { return svgf::extraBuffers(settings_); }

  void resizeHistory(int w, int h) override {
    reprojection_.allocate(ctx_, w, h, 8);
    gradient_.allocate(ctx_, w, h, 2);
    for (auto& l : levels_) l.allocate(ctx_, w, h, 5);
    sigmaScale_.allocate(ctx_, w, h, 1);
    for (auto& v : valid_) v.allocate(ctx_, w, h, 1);
    for (auto& s : streams_) {
      s.demod.allocate(ctx_, w, h, 3);
      s.accumulator.resize(ctx_, w, h);
    }
    sum_.allocate(ctx_, w, h, 3);
    display_.allocate(ctx_, w, h, 3);
    remodulated_.allocate(ctx_, w, h, 3);
    taa_.resize(ctx_, w, h);
    reflections_.resize(ctx_, w, h);
  }
  void resetHistory() override {
    for (auto& s : streams_) s.accumulator.reset();
    reflections_.reset();
    taa_.reset();
  }

  const vk::Planes& process(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous) override {
    const SvgfSettings& s = settings_;
    const int nStreams = chooseStreams(frame);
    const bool lobes = nStreams == 2 && streams_[1].plan.lobe == svgf::Lobe::specular;
    svgf::ReflectionParts parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return frame.has(b); }, lobes);
    mask_ = s.useSampleMask && frame.has(Buffer::SampleMask) ? &frame[Buffer::SampleMask] : nullptr;
    const vk::Planes* albedo = frame.has(Buffer::Albedo) ? &frame[Buffer::Albedo] : nullptr;
    rec.pass("reproject");
    vk::reproject(rec, frame, previous, s.reprojection, reprojection_);
    rec.pass("features");
    vk::atrousGuide(rec, frame, s.maxDepthSlope, gradient_);
    if (parts.classes) {
      rec.pass("reflections");  // Voorhuis: classes, diamond search, reflected features
      reflections_.prepare(rec, frame, previous, s, parts, lobes, reprojection_);
    }
    const vk::GpuAtrousGuide primaryGuide{&frame[Buffer::Depth], &frame[Buffer::Normal], &gradient_};
    for (int k = 0; k < nStreams; ++k) {
      GpuStream& st = streams_[k];
      const std::string suffix = nStreams > 1 ? std::string(".") + st.plan.name : std::string();
      const svgf::GpuReflections::StreamInputs in = reflections_.stream(rec, frame, st.plan, reprojection_, primaryGuide, k);
      const vk::Planes* streamAlbedo = in.albedo;
      const vk::Planes& result = filterStream(rec, frame, st, in, suffix);
      rec.pass("sum" + suffix);
      const bool same = streamAlbedo == albedo;
      struct PC {
        uint32_t width, height, first, divide, times;
      } pc{uint32_t(frame.width), uint32_t(frame.height), k == 0, !same && albedo, !same && streamAlbedo};
      rec.dispatch("svgf_sum",
                   {result, albedo ? vk::Binding(*albedo) : vk::Binding(ctx_.dummy()), sum_,
                    streamAlbedo ? vk::Binding(*streamAlbedo) : vk::Binding(ctx_.dummy())},
                   pc, frame.width, frame.height);
    }
    const vk::Planes* shown = &sum_;
    if (s.fireflyMedian) {
      rec.pass("median");
      struct PC {
        uint32_t width, height, hasRoughness;
      } pc{uint32_t(frame.width), uint32_t(frame.height), frame.has(Buffer::Roughness)};
      rec.dispatch("median3x3", {sum_, frame.bindingOf(Buffer::Roughness, ctx_), display_}, pc, frame.width,
                   frame.height);
      shown = &display_;
    }
    rec.pass("remodulate");
    vk::remodulate(rec, *shown, albedo, remodulated_);
    notes_ = std::move(parts.notes);
    rec.pass("taa");
    if (!s.taa.taa) return remodulated_;
    return taa_.run(rec, reflections_.taaMotion(rec, frame, reprojection_), remodulated_, s.taa.taaAlpha);
  }

 private:
  int chooseStreams(const vk::GpuFrame& f) {
    svgf::StreamPlan plan[2];
    const int n = svgf::planStreams(settings_.components, [&](Buffer b) { return f.has(b); }, plan, settings_.preferLobes);
    for (int k = 0; k < n; ++k) {
      GpuStream& st = streams_[k];
      if (st.plan.buffer != plan[k].buffer) st.accumulator.reset();  // another stream's history is meaningless
      st.plan = plan[k];
    }
    return n;
  }

  // Demodulate, accumulate, estimate the variance, filter; returns the level holding the result.
  const vk::Planes& filterStream(vk::Recorder& rec, const vk::GpuFrame& frame, GpuStream& st,
                                 const svgf::GpuReflections::StreamInputs& in, const std::string& suffix) {
    const SvgfSettings& s = settings_;
    const uint32_t lum = luminanceMode(s.luminance);
    const size_t planeBytes = size_t(frame.width) * frame.height * 4;
    rec.pass("demodulate" + suffix);
    vk::demodulate(rec, frame[st.plan.buffer], in.albedo, st.demod);
    const vk::Planes* clip = nullptr;
    if (reflections_.parts().clipping) {
      rec.pass("clip" + suffix);  // Voorhuis Sec. 4.2.3
      clip = reflections_.clipBox(rec, st.demod, st.plan, s);
    }
    rec.pass("accumulate" + suffix);
    st.accumulator.run(rec, *in.reprojection, st.demod, s.alphaColor, s.alphaMoments, s.maxHistoryLength, lum,
                       s.momentsTrueAverage, mask_, in.alpha, clip);
    const int normalExponent = std::max(1, int(std::lround(s.sigmaNormal)));
    rec.pass("variance" + suffix);
    {
      struct PC {
        uint32_t width, height;
        float shortHistoryFrames;
        int32_t radius;
        float sigmaDepth, depthEpsilon;
        int32_t normalExponent;
        uint32_t luminanceMode, flags;
      } pc{uint32_t(frame.width), uint32_t(frame.height), float(s.shortHistoryFrames), s.spatialVarianceRadius,
           s.sigmaDepth, s.depthEpsilon, normalExponent, lum, 0};
      if (s.shortHistory == SvgfShortHistory::spatialEstimate && s.shortHistoryFrames > 0) pc.flags |= 1;
      if (s.spatialVarianceFromMoments) pc.flags |= 2;
      if (s.shortHistory == SvgfShortHistory::disableLuminanceWeight) pc.flags |= 4;
      if (s.shortHistoryBandwidth) pc.flags |= 8;
      rec.dispatch("svgf_variance",
                   {*in.guide.depth, *in.guide.normal, *in.guide.gradient, st.accumulator.current(), st.demod,
                    levels_[0], sigmaScale_},
                   pc, frame.width, frame.height);
      if (s.variancePrefilter == SvgfVariancePrefilter::once) {
        vk::gaussian3x3(rec, levels_[0], 4, levels_[2], 4);
        rec.copy(levels_[2].buffer, levels_[0].buffer, planeBytes, 4 * planeBytes, 4 * planeBytes);
      }
    }
    const int n = s.atrousIterations;
    const bool propagate = s.varianceFiltering && !(st.plan.indirect && !s.indirectVarianceFiltering);
    int cur = 0;
    for (int i = 0; i < n; ++i) {
      rec.pass("atrous" + std::to_string(i + 1) + suffix);
      vk::GpuAtrousLevel lv;
      lv.radius = s.kernel == SvgfKernel::b3spline5x5 ? 2 : 1;
      lv.step = levelStep(s.levelOrder, n, i);
      lv.sigmaDepth = s.sigmaDepth;
      lv.depthEpsilon = s.depthEpsilon;
      lv.normalExponent = normalExponent;
      lv.sigmaLuminance = s.sigmaLuminance;
      lv.luminanceEpsilon = s.luminanceEpsilon;
      lv.prefilterVariance = s.variancePrefilter == SvgfVariancePrefilter::everyLevel;
      lv.varianceScale = s.luminanceScale == SvgfLuminanceScale::variance;
      lv.sigmaScale = &sigmaScale_;
      lv.propagateVariance = propagate && i + 1 < n;  // the last level's variance is not used
      lv.luminanceMode = lum;
      lv.spatialFalloff = in.falloff;  // Voorhuis Eq. 6
      if (mask_) {
        // Level-0 validity is historyLength > 0 (the CPU's markValid), read straight from the
        // accumulator's length plane; later levels read the previous level's validity.
        if (i == 0) {
          lv.validIn = &st.accumulator.current();
          lv.validInPlane = 5;
        } else {
          lv.validIn = &valid_[(i - 1) & 1];
        }
        lv.validOut = &valid_[i & 1];
      }
      vk::atrousLevel(rec, in.guide, lv, levels_[cur], levels_[cur ^ 1]);
      cur ^= 1;
      // The feedback level's output becomes next frame's colour history (Schied Sec. 4.3).
      if (i + 1 == s.feedbackLevel) {
        if (mask_) {
          struct PC {
            uint32_t width, height;
          } pc{uint32_t(frame.width), uint32_t(frame.height)};
          rec.dispatch("svgf_feedback_sampled", {levels_[cur], *mask_, st.accumulator.current()}, pc, frame.width,
                       frame.height);
        } else {
          rec.copy(levels_[cur].buffer, st.accumulator.current().buffer, 3 * planeBytes);
        }
      }
    }
    if (n == 0) rec.copy(st.accumulator.current().buffer, levels_[cur].buffer, 3 * planeBytes);
    return levels_[cur];
  }

  // Tap spacing of executed level i of n (svgf::levelSteps).
  static int levelStep(SvgfLevelOrder order, int n, int i) {
    switch (order) {
      case SvgfLevelOrder::coarseToFine: return 1 << (n - 1 - i);
      case SvgfLevelOrder::firstThenCoarseToFine: return i == 0 ? 1 : 1 << (n - i);
      default: return 1 << i;
    }
  }

  vk::Planes reprojection_, gradient_, levels_[3], sigmaScale_, sum_, display_, remodulated_;
  vk::Planes valid_[2];                  // a-trous validity per level in the progressive mode
  const vk::Planes* mask_ = nullptr;     // this frame's sample mask, or null (dense)
  GpuStream streams_[kMaxStreams];
  svgf::GpuReflections reflections_;
  vk::GpuTaa taa_;
};

}  // namespace

std::unique_ptr<Denoiser> createSvgfVulkan(vk::Context& ctx) { return std::make_unique<SvgfVulkan>(ctx); }

}  // namespace rtd
#endif
