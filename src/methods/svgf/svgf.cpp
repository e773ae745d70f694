// Method "svgf": spatiotemporal variance-guided filtering (Schied et al. 2017) and the
// variants of Dundr, Gersthofer and Voorhuis as settings. Per radiance stream: demodulate,
// accumulate colour and luminance moments, estimate the variance, filter with the a-trous
// wavelet (feeding one level back as colour history); then sum the streams, remodulate and
// apply TAA. docs/methods/svgf.md has the details.
#include <cmath>

#include "backend/cpu/cpu_denoiser.h"
#include "core/parallel.h"
#include "methods/svgf/svgf_passes.h"
#include "methods/svgf/svgf_reflections.h"
#include "passes/demodulation.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/svgf.h"

namespace rtd {

namespace {

constexpr int kMaxStreams = 2;

MomentLuminance toMomentLuminance(SvgfLuminance l) {
  switch (l) {
    case SvgfLuminance::rec601: return MomentLuminance::Rec601;
    case SvgfLuminance::cieLightness: return MomentLuminance::CieLightness;
    default: return MomentLuminance::Rec709;
  }
}

// One radiance stream (Color, or one half of a split) and its history.
struct Stream {
  svgf::StreamPlan plan{Buffer::Color, "color", true, false};  // which buffer, and how it is filtered
  Plane3 demod;
  TemporalAccumulator accumulator;
};

class SvgfCpu final : public CpuDenoiser<SvgfSettings> {
 public:
  using CpuDenoiser::CpuDenoiser;
  std::vector<Buffer> requiredBuffers() const override { return {Buffer::Color, Buffer::Normal, Buffer::Depth}; }
  std::vector<Buffer> extraBuffers() const override { return svgf::extraBuffers(settings_); }

 protected:
  void resizeHistory(int w, int h) override {
    const int pad = requiredPad();
    pad_ = pad;
    guide_.resize(w, h, pad);
    reflections_.resize(w, h, pad);
    for (auto& im : levels_) im.resize(w, h, pad);
    sigmaScale_.resize(w, h, pad);
    for (auto& v : valid_) v.resize(w, h, pad);
    for (auto& v : scratch_) v.resize(w, h, pad);
    for (auto& s : streams_) {
      rtd::resize(s.demod, w, h);
      s.accumulator.resize(w, h);
    }
    rtd::resize(sum_, w, h);
    rtd::resize(display_, w, h);
    taa_.resize(w, h);
  }
  void resetHistory() override {
    for (auto& s : streams_) s.accumulator.reset();
    reflections_.reset();
    taa_.reset();
  }

  const Plane3& process(const FrameData& frame, const FrameData* previous, Plane3& /*out*/, FrameStats& stats) override {
    const SvgfSettings& s = settings_;
    if (requiredPad() > pad_) {  // more levels than allocated for: settings changed
      resizeHistory(frame.width, frame.height);
      resetHistory();
      previous = nullptr;
    }
    const int nStreams = chooseStreams(frame);
    const bool lobes = nStreams == 2 && streams_[1].plan.lobe == svgf::Lobe::specular;
    // Before any history is touched: an explicitly requested part without its buffers throws.
    svgf::ReflectionParts parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return frame.has(b); }, lobes);
    mask_ = s.useSampleMask && frame.has(Buffer::SampleMask) ? &frame.plane(Buffer::SampleMask) : nullptr;
    const auto* albedo = frame.has(Buffer::Albedo) ? &frame.planes(Buffer::Albedo) : nullptr;
    {
      PassTimer t(stats, "reproject");
      reproject(frame, previous, s.reprojection, reprojection_);
    }
    {
      PassTimer t(stats, "features");
      guide_.build(frame.plane(Buffer::Depth), frame.planes(Buffer::Normal),
                   frame.has(Buffer::DepthGradient) ? &frame.planes(Buffer::DepthGradient) : nullptr, s.maxDepthSlope);
    }
    if (parts.classes) {
      PassTimer t(stats, "reflections");  // Voorhuis: classes, diamond search, reflected features
      reflections_.prepare(frame, previous, s, parts, lobes, reprojection_);
    }
    for (int k = 0; k < nStreams; ++k) {
      Stream& st = streams_[k];
      const std::string suffix = nStreams > 1 ? std::string(".") + st.plan.name : std::string();
      const svgf::Reflections::StreamInputs in = reflections_.stream(frame, st.plan, reprojection_, guide_, k);
      filterStream(frame, st, in, suffix, stats);
      PassTimer t(stats, "sum" + suffix);
      addStream(k == 0, in.albedo, albedo);
    }
    stats.notes = std::move(parts.notes);
    Plane3* shown = &sum_;
    if (s.fireflyMedian) {
      PassTimer t(stats, "median");
      svgf::median3x3(sum_, frame.has(Buffer::Roughness) ? &frame.plane(Buffer::Roughness) : nullptr, display_);
      shown = &display_;
    }
    {
      PassTimer t(stats, "remodulate");
      remodulate(*shown, albedo);
    }
    if (!s.taa.taa) return *shown;
    PassTimer t(stats, "taa");
    return taa_.run(reflections_.taaMotion(frame, reprojection_), *shown, s.taa.taaAlpha);
  }

 private:
  int requiredPad() const {
    const int r = settings_.kernel == SvgfKernel::b3spline5x5 ? 2 : 1;
    const int maxStep = settings_.atrousIterations > 0 ? 1 << (settings_.atrousIterations - 1) : 1;
    return std::max({r * maxStep, settings_.spatialVarianceRadius, 8});
  }

  // Which streams this frame has, per the `components` setting.
  int chooseStreams(const FrameData& f) {
    svgf::StreamPlan plan[2];
    const int n = svgf::planStreams(settings_.components, [&](Buffer b) { return f.has(b); }, plan, settings_.preferLobes);
    for (int k = 0; k < n; ++k) {
      Stream& st = streams_[k];
      if (st.plan.buffer != plan[k].buffer) st.accumulator.reset();  // another stream's history is meaningless
      st.plan = plan[k];
    }
    return n;
  }

  void filterStream(const FrameData& frame, Stream& st, const svgf::Reflections::StreamInputs& in,
                    const std::string& suffix, FrameStats& stats) {
    const SvgfSettings& s = settings_;
    const MomentLuminance lum = toMomentLuminance(s.luminance);
    {
      PassTimer t(stats, "demodulate" + suffix);
      demodulate(frame.planes(st.plan.buffer), in.albedo, st.demod);
    }
    AccumulationOptions opt;
    if (reflections_.parts().clipping) {
      PassTimer t(stats, "clip" + suffix);  // Voorhuis Sec. 4.2.3
      reflections_.clipBoxes(st.demod, st.plan, s, opt.clipLow, opt.clipHigh);
    }
    {
      PassTimer t(stats, "accumulate" + suffix);
      opt.luminance = lum;
      opt.cumulativeMoments = s.momentsTrueAverage;
      opt.sampleMask = mask_;
      opt.alphaPlane = in.alpha;
      st.accumulator.run(*in.reprojection, st.demod, s.alphaColor, s.alphaMoments, s.maxHistoryLength, opt);
    }
    const int normalExponent = std::max(1, int(std::lround(s.sigmaNormal)));
    {
      PassTimer t(stats, "variance" + suffix);
      svgf::VarianceInputs vin{&st.accumulator.historyLength(), &st.accumulator.moment1(), &st.accumulator.moment2(),
                              &st.demod, &st.accumulator.color()};
      svgf::VarianceParams p;
      p.shortHistoryFrames = s.shortHistoryFrames;
      p.shortHistory = s.shortHistory;
      p.radius = s.spatialVarianceRadius;
      p.fromMoments = s.spatialVarianceFromMoments;
      p.sigmaDepth = s.sigmaDepth;
      p.depthEpsilon = s.depthEpsilon;
      p.normalExponent = normalExponent;
      p.luminance = lum;
      svgf::estimateVariance(*in.guide, vin, p, levels_[0], scratch_);
      svgf::luminanceSigmaScale(st.accumulator.historyLength(), s, sigmaScale_);
      if (mask_) markValid(st.accumulator.historyLength(), valid_[0]);
      if (s.variancePrefilter == SvgfVariancePrefilter::once) {
        gaussian3x3(levels_[0].var, levels_[2].var);
        std::swap(levels_[0].var, levels_[2].var);
      }
    }
    const int n = s.atrousIterations;
    int steps[8];
    svgf::levelSteps(s.levelOrder, n, steps);
    const bool propagate = s.varianceFiltering && !(st.plan.indirect && !s.indirectVarianceFiltering);
    int cur = 0;
    for (int i = 0; i < n; ++i) {
      PassTimer t(stats, "atrous" + std::to_string(i + 1) + suffix);
      AtrousImage& src = levels_[cur];
      AtrousImage& dst = levels_[cur ^ 1];
      AtrousLevel lv;
      lv.kernel = s.kernel == SvgfKernel::b3spline5x5 ? AtrousKernel::B3Spline5x5 : AtrousKernel::Binomial3x3;
      lv.step = steps[i];
      lv.sigmaDepth = s.sigmaDepth;
      lv.depthEpsilon = s.depthEpsilon;
      lv.normalExponent = normalExponent;
      lv.sigmaLuminance = s.sigmaLuminance;
      lv.luminanceEpsilon = s.luminanceEpsilon;
      lv.prefilterVariance = s.variancePrefilter == SvgfVariancePrefilter::everyLevel;
      lv.varianceScale = s.luminanceScale == SvgfLuminanceScale::variance;
      lv.sigmaScale = &sigmaScale_;
      // The last level's variance is not used any more.
      lv.propagateVariance = propagate && i + 1 < n;
      lv.luminance = lum;
      lv.spatialFalloff = in.falloff;  // Voorhuis Eq. 6
      if (mask_) {
        lv.validIn = &valid_[cur];
        lv.validOut = &valid_[cur ^ 1];
      }
      atrousLevel(*in.guide, lv, src, dst);
      if (!lv.propagateVariance) std::swap(src.var, dst.var);  // keep the unfiltered variance
      cur ^= 1;
      if (i + 1 == s.feedbackLevel) {
        // The first level's output becomes next frame's colour history (Schied Sec. 4.3).
        Plane3& history = st.accumulator.color();
        if (mask_) feedbackSampled(levels_[cur], *mask_, history);
        else for (int c = 0; c < 3; ++c) levels_[cur].color[c].copyTo(history[c]);
      }
    }
    // Result of this stream: levels_[cur].color (or the accumulation when n == 0).
    if (n == 0)
      for (int c = 0; c < 3; ++c) levels_[cur].color[c].copyFrom(st.accumulator.color()[c]);
    result_ = cur;
  }

  // sum_ (+)= this stream's filtered illumination, remodulated by the stream's own colour
  // `streamAlbedo` (null: not demodulated) and divided by `albedo`, so that the shared
  // remodulation by `albedo` restores it exactly.
  void addStream(bool first, const std::vector<Plane>* streamAlbedo, const std::vector<Plane>* albedo) {
    const AtrousImage& r = levels_[result_];
    const int w = sum_[0].width;
    const bool same = streamAlbedo == albedo;  // the common case: nothing to convert
    const std::vector<Plane>* times = same ? nullptr : streamAlbedo;
    const std::vector<Plane>* divide = same ? nullptr : albedo;
    parallelRows(sum_[0].height, [&](int y) {
      for (int c = 0; c < 3; ++c) {
        const float* in = r.color[c].row(y);
        float* o = sum_[c].row(y);
        const float* m = times ? (*times)[c].row(y) : nullptr;
        const float* a = divide ? (*divide)[c].row(y) : nullptr;
        for (int x = 0; x < w; ++x) {
          float v = in[x];
          if (m) v *= demodulationFactor(m[x]);
          if (a) v /= demodulationFactor(a[x]);
          o[x] = first ? v : o[x] + v;
        }
      }
    });
  }

  // Level-0 validity: pixels with any accumulated data.
  static void markValid(const Plane& length, PaddedPlane& valid) {
    const int w = length.width;
    parallelRows(length.height, [&](int y) {
      const float* n = length.row(y);
      float* v = valid.row(y);
      for (int x = 0; x < w; ++x) v[x] = n[x] > 0.0f ? 1.0f : 0.0f;
    });
  }

  // Dundr Sec. 5: feeding the filtered level back everywhere would blur untouched samples
  // again every frame; only pixels sampled this frame take the filtered value.
  static void feedbackSampled(const AtrousImage& level, const Plane& mask, Plane3& history) {
    const int w = mask.width;
    parallelRows(mask.height, [&](int y) {
      const float* m = mask.row(y);
      for (int c = 0; c < 3; ++c) {
        const float* in = level.color[c].row(y);
        float* o = history[c].row(y);
        for (int x = 0; x < w; ++x)
          if (m[x] != 0.0f) o[x] = in[x];
      }
    });
  }

  Reprojection reprojection_;
  AtrousGuide guide_;
  svgf::Reflections reflections_;
  AtrousImage levels_[3];
  PaddedPlane sigmaScale_;
  PaddedPlane valid_[2], scratch_[2];
  const Plane* mask_ = nullptr;
  Stream streams_[kMaxStreams];
  Plane3 sum_, display_;
  Taa taa_;
  int pad_ = 0;
  int result_ = 0;
};

}  // namespace

std::unique_ptr<Denoiser> createSvgfCpu(tbb::task_arena& arena) { return std::make_unique<SvgfCpu>(arena); }

}  // namespace rtd
