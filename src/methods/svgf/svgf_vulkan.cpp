// Method "svgf" on the Vulkan backend: the passes of svgf.cpp, pass for pass, as compute
// shaders (shared ones in src/backend/vulkan/shaders, SVGF's own in shaders/ here). Every
// setting of SvgfSettings is honoured, variants and the progressive sub-1-spp mode included.
#if defined(RTD_HAS_VULKAN) && __has_include("rtd/methods/svgf.h")
#include "backend/vulkan/vulkan_denoiser.h"
#include "core/stereo_pair.h"
#include "methods/svgf/gersthofer_vulkan.h"
#include "methods/svgf/svgf_filter_vulkan.h"
#include "methods/svgf/svgf_passes.h"
#include "methods/svgf/svgf_reflections_vulkan.h"
#include "rtd/methods/svgf.h"

namespace rtd {

namespace {

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

  // For the two-view denoiser (SvgfStereoVulkan): the eye's pipeline and frame while recording.
  svgf::GpuGersthoferEye& gersthoferEye() { return *gersthofer_; }
  const vk::GpuFrame& frame() const { return recordingFrame(); }

 protected:
  std::vector<Buffer> extraBuffers() const override { return svgf::extraBuffers(settings_); }
  // Gersthofer's categories (his Table 5.4), as on the CPU.
  std::vector<MemoryUse> methodMemory() const override {
    return gersthofer_ ? gersthofer_->memory() : std::vector<MemoryUse>{};
  }

  void resizeHistory(int w, int h) override {
    reprojection_.allocate(ctx_, w, h, 8);
    gradient_.allocate(ctx_, w, h, 2);
    guideNormal_.allocate(ctx_, w, h, 3);
    filter_.resize(ctx_, w, h);
    // As svgf.cpp: a stream's planes when a frame first has it (chooseStreams), the median's
    // when it runs.
    for (auto& s : streams_) s = GpuStream{};
    sum_.allocate(ctx_, w, h, 3);
    display_ = {};
    remodulated_.allocate(ctx_, w, h, 3);
    taa_.resize(w, h);
    reflections_.resize(ctx_, w, h);
    if (gersthofer_) gersthofer_->resize(ctx_, w, h);
  }
  void resetHistory() override {
    for (auto& s : streams_) s.accumulator.reset();
    reflections_.reset();
    taa_.reset();
    if (gersthofer_) gersthofer_->reset();
  }

  // Gersthofer's pipeline (gersthofer_vulkan.h) in the two halves a two-view denoiser records
  // around the exchange between the eyes; other settings run process() in the second half.
  void processFront(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous) override {
    if (settings_.components != SvgfComponents::composite) return;
    if (!gersthofer_) {
      gersthofer_ = std::make_unique<svgf::GpuGersthoferEye>();
      gersthofer_->resize(ctx_, frame.width, frame.height);
    }
    gersthofer_->front(rec, frame, previous, settings_);
  }
  const vk::Planes& processBack(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous) override {
    if (settings_.components != SvgfComponents::composite) return process(rec, frame, previous);
    return gersthofer_->back(rec, frame, settings_, resultHasEmission_);
  }

  const vk::Planes& process(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous) override {
    const SvgfSettings& s = settings_;
    resultHasEmission_ = false;
    if (s.components == SvgfComponents::composite) {
      processFront(rec, frame, previous);
      return processBack(rec, frame, previous);
    }
    const int nStreams = chooseStreams(frame);
    const bool lobes = nStreams == 2 && streams_[1].plan.lobe == svgf::Lobe::specular;
    svgf::ReflectionParts parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return frame.has(b); }, lobes);
    mask_ = s.useSampleMask && frame.has(Buffer::SampleMask) ? &frame[Buffer::SampleMask] : nullptr;
    const vk::Planes* albedo = frame.has(Buffer::Albedo) ? &frame[Buffer::Albedo] : nullptr;
    rec.pass("reproject");
    vk::reproject(rec, frame, previous, s.reprojection, reprojection_);
    rec.pass("features");
    vk::atrousGuide(rec, frame, s.maxDepthSlope, gradient_);
    // Without parts too: it records that this frame has none (stream(), the clipping test and
    // taaMotion() read them; a previous frame's, before a change of settings, would be stale).
    if (parts.classes) rec.pass("reflections");  // Voorhuis: classes, diamond search, reflected features
    reflections_.prepare(rec, frame, previous, s, parts, lobes, reprojection_);
    // Issue 12: emitter pixels weigh 0 as neighbours (a zero guide normal).
    const vk::Planes& guideNormal = vk::emitterGuideNormal(rec, frame, s.emitters, guideNormal_);
    const svgf::GpuGuide primaryGuide{&frame[Buffer::Depth], &guideNormal, &gradient_};
    for (int k = 0; k < nStreams; ++k) {
      GpuStream& st = streams_[k];
      const std::string suffix = nStreams > 1 ? std::string(".") + st.plan.name : std::string();
      const vk::Planes* streamAlbedo = nullptr;
      const vk::Planes* result = &frame[st.plan.buffer];  // components = diffuse: the specular lobe as it comes
      if (st.plan.filtered) {
        const svgf::GpuReflections::StreamInputs in = reflections_.stream(rec, frame, st.plan, reprojection_, primaryGuide, k);
        streamAlbedo = in.albedo;
        result = &filterStream(rec, frame, st, in, suffix);
      }
      if (s.fireflyMedian && st.plan.lobe == svgf::Lobe::diffuse && st.plan.filtered) {
        // The diffuse lobe's median, everywhere (as svgf.cpp).
        rec.pass("median" + suffix);
        vk::allocateOnce(display_, ctx_, frame.width, frame.height, 3);
        struct PC {
          uint32_t width, height, hasRoughness, skipWhenMasked;
        } pc{uint32_t(frame.width), uint32_t(frame.height), 0, 0};
        rec.dispatch("median3x3", {*result, ctx_.dummy(), display_, vk::Binding(ctx_.dummy())}, pc, frame.width,
                     frame.height);
        result = &display_;
      }
      rec.pass("sum" + suffix);
      const bool same = streamAlbedo == albedo;
      struct PC {
        uint32_t width, height, first, divide, times;
      } pc{uint32_t(frame.width), uint32_t(frame.height), k == 0, !same && albedo, !same && streamAlbedo};
      rec.dispatch("svgf_sum",
                   {*result, albedo ? vk::Binding(*albedo) : vk::Binding(ctx_.dummy()), sum_,
                    streamAlbedo ? vk::Binding(*streamAlbedo) : vk::Binding(ctx_.dummy())},
                   pc, frame.width, frame.height);
    }
    const vk::Planes* shown = &sum_;
    if (s.fireflyMedian && !lobes) {
      rec.pass("median");
      vk::allocateOnce(display_, ctx_, frame.width, frame.height, 3);
      struct PC {
        uint32_t width, height, hasRoughness, skipWhenMasked;
      } pc{uint32_t(frame.width), uint32_t(frame.height), frame.has(Buffer::Roughness), 0};
      rec.dispatch("median3x3", {sum_, frame.bindingOf(Buffer::Roughness, ctx_), display_, vk::Binding(ctx_.dummy())}, pc,
                   frame.width, frame.height);
      shown = &display_;
    }
    rec.pass("remodulate");
    vk::remodulate(rec, *shown, albedo, remodulated_);
    notes_ = std::move(parts.notes);
    rec.pass("taa");
    if (!s.taa.taa) return remodulated_;
    // The own-surface box's keys (as svgf.cpp): object id, the classes where computed, emitters.
    const bool keyed = s.taa.taaOwnSurface &&
                       vk::taaSurfaceKeys(rec, frame, &s.emitters, parts.classes ? &reflections_.classes() : nullptr, taaKeys_);
    return taa_.run(rec, reflections_.taaMotion(rec, frame, reprojection_, s.taaGlossyReflectionMotion, s.taaMirrorHistory),
                    remodulated_, s.taa,
                    keyed ? &taaKeys_ : nullptr);
  }

 private:
  int chooseStreams(const vk::GpuFrame& f) {
    svgf::StreamPlan plan[2];
    const int n = svgf::planStreams(settings_.components, [&](Buffer b) { return f.has(b); }, plan, settings_.preferLobes);
    for (int k = 0; k < n; ++k) {
      GpuStream& st = streams_[k];
      if (st.plan.buffer != plan[k].buffer) st.accumulator.reset();  // another stream's history is meaningless
      st.plan = plan[k];
      if (st.demod.buffer.empty()) {  // the first frame with a k-th stream at this size (resizeHistory)
        st.demod.allocate(ctx_, f.width, f.height, 3);
        st.accumulator.resize(ctx_, f.width, f.height);
        st.accumulator.reset();  // device memory starts undefined: lengths 0 before the first run
      }
    }
    return n;
  }

  // Demodulate and accumulate one stream, then the shared SVGF filter (variance, a-trous
  // levels, feedback); returns the planes holding the result. `in`: the stream's reprojection,
  // guide, demodulation colour and Voorhuis inputs (svgf::GpuReflections::stream).
  const vk::Planes& filterStream(vk::Recorder& rec, const vk::GpuFrame& frame, GpuStream& st,
                                 const svgf::GpuReflections::StreamInputs& in, const std::string& suffix) {
    const SvgfSettings& s = settings_;
    const svgf::FilterParams p = svgf::filterParams(s, st.plan.indirect);
    rec.pass("demodulate" + suffix);
    vk::demodulate(rec, frame[st.plan.buffer], in.albedo, st.demod);
    const vk::Planes* clip = nullptr;
    if (reflections_.parts().clipping) {
      rec.pass("clip" + suffix);  // Voorhuis Sec. 4.2.3
      clip = reflections_.clipBox(rec, st.demod, st.plan, s);
    }
    rec.pass("accumulate" + suffix);
    st.accumulator.run(rec, *in.reprojection, st.demod, s.alphaColor, s.alphaMoments, s.maxHistoryLength,
                       uint32_t(p.variance.luminance), s.momentsTrueAverage, mask_, in.alpha, clip);
    return filter_.run(rec, *in.guide.depth, *in.guide.normal, *in.guide.gradient, st.accumulator, st.demod, mask_, p,
                       suffix, {.spatialFalloff = in.falloff, .surfaceKey = in.surfaceKey});
  }

  vk::Planes reprojection_, gradient_, guideNormal_, sum_, display_, remodulated_;
  svgf::GpuFilter filter_;
  const vk::Planes* mask_ = nullptr;     // this frame's sample mask, or null (dense)
  GpuStream streams_[svgf::kMaxStreams];
  svgf::GpuReflections reflections_;
  vk::GpuTaa taa_;
  vk::Planes taaKeys_;  // TaaSettings::taaOwnSurface
  std::unique_ptr<svgf::GpuGersthoferEye> gersthofer_;  // components = composite
};

// Method "svgf" on two views (rtd/stereo.h), Vulkan: with composite and eyeReprojection both
// eyes are recorded into one command buffer, their indirect diffuse exchanged between the two
// halves (vk::eyeReproject, both directions); otherwise two single-view denoisers.
class SvgfStereoVulkan final : public StereoPair {
 public:
  explicit SvgfStereoVulkan(vk::Context& ctx)
      : StereoPair(std::make_unique<SvgfVulkan>(ctx), std::make_unique<SvgfVulkan>(ctx)) {}

  void denoise(const StereoFrameInputs& in, const ImageView& left, const ImageView& right) override {
    const SvgfSettings s = getSettings<SvgfSettings>();
    if (s.components != SvgfComponents::composite || !s.eyeReprojection) {
      StereoPair::denoise(in, left, right);
      return;
    }
    validate(in, left, right);
    if (in.eye[0].cameraCut || in.eye[1].cameraCut) reset();
    auto& a = static_cast<SvgfVulkan&>(*eyes_[0]);
    auto& b = static_cast<SvgfVulkan&>(*eyes_[1]);
    vk::VulkanDenoiserBase::denoiseTwoViews(a, b, in.eye[0], in.eye[1], left, right, [&](vk::Recorder& rec) {
      const vk::GpuFrame &fa = a.frame(), &fb = b.frame();
      auto canShare = [](const vk::GpuFrame& f) {
        return f.has(Buffer::Position) && f.has(Buffer::Normal) && f.has(Buffer::Depth) && f.cameraValue.valid;
      };
      if (!canShare(fa) || !canShare(fb)) return;
      svgf::GpuGersthoferEye &ea = a.gersthoferEye(), &eb = b.gersthoferEye();
      // Each direction from the un-exchanged light; the source taps need data (length > 0).
      vk::eyeReproject(rec, fa, fb, &eb.history(), 5, s.reprojection, s.eyeBlend, ea.indirectDiffuse(),
                       eb.indirectDiffuse(), ea.shared());
      vk::eyeReproject(rec, fb, fa, &ea.history(), 5, s.reprojection, s.eyeBlend, eb.indirectDiffuse(),
                       ea.indirectDiffuse(), eb.shared());
    });
    // Each eye's passes without the span it waited for the other; the exchange (both
    // directions, recorded with the left eye) once.
    for (int e = 0; e < 2; ++e) {
      FrameStats st = eyes_[e]->stats();
      std::erase_if(st.passes, [](const PassTiming& p) {
        return p.name == "(other eye)" || p.name == "gpu total" || p.name == "gpu filter";
      });
      eyeStats_[e] = std::move(st);
    }
    stats_ = combineEyeStats(eyeStats_[0], eyeStats_[1]);
    stats_.totalMilliseconds = eyeStats_[1].totalMilliseconds;  // both eyes ran in one submission
  }
};

}  // namespace

std::unique_ptr<Denoiser> createSvgfVulkan(vk::Context& ctx) { return std::make_unique<SvgfVulkan>(ctx); }
std::unique_ptr<StereoDenoiser> createSvgfStereoVulkan(vk::Context& ctx) { return std::make_unique<SvgfStereoVulkan>(ctx); }

}  // namespace rtd
#endif
