// Method "svgf": spatiotemporal variance-guided filtering (Schied et al. 2017) and the
// variants of Dundr, Gersthofer and Voorhuis as settings. Per radiance stream: demodulate,
// accumulate colour and luminance moments, estimate the variance, filter with the a-trous
// wavelet (feeding one level back as colour history); then sum the streams, remodulate and
// apply TAA. docs/methods/svgf.md has the details.
#include <cmath>

#include "backend/cpu/cpu_denoiser.h"
#include "core/parallel.h"
#include "methods/svgf/gersthofer.h"
#include "methods/svgf/svgf_filter.h"
#include "methods/svgf/svgf_passes.h"
#include "passes/demodulation.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/svgf.h"

namespace rtd {

namespace {

constexpr int kMaxStreams = 2;

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
    guide_.resize(w, h, pad);
    filter_.resize(w, h, pad);
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
    taa_.reset();
    if (gersthofer_) gersthofer_->reset();
  }
  void visitMethodPlanes(const PlaneVisitor& visit) const override {
    reprojection_.forEachPlane(visit);
    guide_.forEachPlane(visit);
    filter_.forEachPlane(visit);
    for (const auto& st : streams_) {
      visitPlanes(visit, "demodulated", st.demod);
      st.accumulator.forEachPlane(visit);
    }
    visitPlanes(visit, "sum", sum_);
    visitPlanes(visit, "display", display_);
    taa_.forEachPlane(visit);
    if (gersthofer_) gersthofer_->forEachPlane(visit);
  }

  const Plane3& process(const FrameData& frame, const FrameData* previous, Plane3& /*out*/, FrameStats& stats) override {
    const SvgfSettings& s = settings_;
    if (requiredPad() > filter_.pad()) {  // more levels than allocated for: settings changed
      resizeHistory(frame.width, frame.height);
      resetHistory();
      previous = nullptr;
    }
    resultHasEmission_ = false;
    if (s.components == SvgfComponents::composite) return gersthofer(frame, previous, stats);
    const int nStreams = chooseStreams(frame);
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
    for (int k = 0; k < nStreams; ++k) {
      Stream& st = streams_[k];
      const std::string suffix = nStreams > 1 ? std::string(".") + st.plan.name : std::string();
      const AtrousImage& result = filterStream(frame, st, st.plan.demodulated ? albedo : nullptr, suffix, stats);
      PassTimer t(stats, "sum" + suffix);
      addStream(st, result, k == 0, albedo);
    }
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
    return taa_.run(reprojection_, *shown, s.taa.taaAlpha);
  }

 private:
  int requiredPad() const { return svgf::filterParams(settings_, false).requiredPad(); }

  // Gersthofer's pipeline (gersthofer.h) for one view; a StereoDenoiser runs two of them.
  const Plane3& gersthofer(const FrameData& frame, const FrameData* previous, FrameStats& stats) {
    if (!gersthofer_) gersthofer_ = std::make_unique<svgf::GersthoferEye>();
    gersthofer_->front(frame, previous, settings_, stats);
    const Plane3& result = gersthofer_->back(frame, settings_, stats, resultHasEmission_);
    stats.memory = gersthofer_->memory();
    stats.memory.push_back({"frames", svgf::frameBytes(current_) + svgf::frameBytes(previous_)});
    return result;
  }

  // Which streams this frame has, per the `components` setting.
  int chooseStreams(const FrameData& f) {
    svgf::StreamPlan plan[2];
    const int n = svgf::planStreams(settings_.components, [&](Buffer b) { return f.has(b); }, plan);
    for (int k = 0; k < n; ++k) {
      Stream& st = streams_[k];
      if (st.plan.buffer != plan[k].buffer) st.accumulator.reset();  // another stream's history is meaningless
      st.plan = plan[k];
    }
    return n;
  }

  // Demodulate and accumulate one stream, then the shared SVGF filter (variance, a-trous
  // levels, feedback); returns the filtered image.
  const AtrousImage& filterStream(const FrameData& frame, Stream& st, const std::vector<Plane>* albedo,
                                  const std::string& suffix, FrameStats& stats) {
    const SvgfSettings& s = settings_;
    const svgf::FilterParams p = svgf::filterParams(s, st.plan.indirect);
    {
      PassTimer t(stats, "demodulate" + suffix);
      demodulate(frame.planes(st.plan.buffer), albedo, st.demod);
    }
    {
      PassTimer t(stats, "accumulate" + suffix);
      AccumulationOptions opt;
      opt.luminance = p.variance.luminance;
      opt.cumulativeMoments = s.momentsTrueAverage;
      opt.sampleMask = mask_;
      st.accumulator.run(reprojection_, st.demod, s.alphaColor, s.alphaMoments, s.maxHistoryLength, opt);
    }
    return filter_.run(guide_, st.accumulator, st.demod, mask_, p, stats, suffix);
  }

  // sum_ (+)= this stream's filtered illumination; a non-demodulated stream (specular) is
  // divided by the albedo here so that the shared remodulation restores it exactly.
  void addStream(const Stream& st, const AtrousImage& r, bool first, const std::vector<Plane>* albedo) {
    const int w = sum_[0].width;
    const bool divide = !st.plan.demodulated && albedo;
    parallelRows(sum_[0].height, [&](int y) {
      for (int c = 0; c < 3; ++c) {
        const float* in = r.color[c].row(y);
        float* o = sum_[c].row(y);
        const float* a = divide ? (*albedo)[c].row(y) : nullptr;
        for (int x = 0; x < w; ++x) {
          const float v = a ? in[x] / demodulationFactor(a[x]) : in[x];
          o[x] = first ? v : o[x] + v;
        }
      }
    });
  }

  Reprojection reprojection_;
  AtrousGuide guide_;
  svgf::Filter filter_;
  const Plane* mask_ = nullptr;
  Stream streams_[kMaxStreams];
  Plane3 sum_, display_;
  Taa taa_;
  std::unique_ptr<svgf::GersthoferEye> gersthofer_;  // components = composite
};

}  // namespace

std::unique_ptr<Denoiser> createSvgfCpu(tbb::task_arena& arena) { return std::make_unique<SvgfCpu>(arena); }

}  // namespace rtd
