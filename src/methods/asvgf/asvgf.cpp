// Method "asvgf": adaptive SVGF (Schied et al. 2018) as the Higginson thesis implements it
// (Sec. 2.3, 3.3): per frame reproject, compute the temporal gradient of each 3x3 stratum from
// the re-shaded gradient samples, filter it with its own a-trous levels on the 1/3-resolution
// grid, accumulate colour and moments with the adaptive history N' and alpha, then SVGF's
// variance, a-trous levels and feedback (svgf::Filter), remodulation and TAA.
// docs/methods/asvgf.md has the details.
#include <algorithm>
#include <cmath>

#include "backend/cpu/cpu_denoiser.h"
#include "core/parallel.h"
#include "methods/asvgf/asvgf_passes.h"
#include "methods/svgf/svgf_filter.h"
#include "passes/demodulation.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "passes/taa_keys.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/asvgf.h"

namespace rtd {

namespace {

class AsvgfCpu final : public CpuDenoiser<AsvgfSettings> {
 public:
  using CpuDenoiser::CpuDenoiser;
  std::vector<Buffer> requiredBuffers() const override { return asvgf::requiredBuffers(settings_); }
  std::vector<Buffer> extraBuffers() const override { return asvgf::extraBuffers(settings_); }

 protected:
  void resizeHistory(int w, int h) override {
    const svgf::FilterParams p = asvgf::filterParams(settings_);
    guide_.resize(w, h, p.requiredPad());
    filter_.resize(w, h, p.requiredPad());
    gradientPad_ = asvgf::gradientPad(settings_.gradientIterations);
    gradient_.resize(w, h, gradientPad_);
    normals_.resize(3);
    for (auto& n : normals_) n.resize(w, h);
    rtd::resize(demod_, w, h);
    rtd::resize(result_, w, h);
    accumulator_.resize(w, h);
    taa_.resize(w, h);
  }
  void resetHistory() override {
    accumulator_.reset();
    taa_.reset();
  }
  void visitMethodPlanes(const PlaneVisitor& visit) const override {
    reprojection_.forEachPlane(visit);
    guide_.forEachPlane(visit);
    for (const Plane& n : normals_) visitPlane(visit, "filter normal", n);
    visitPlanes(visit, "demodulated", demod_);
    visitPlanes(visit, "result", result_);
    gradient_.forEachPlane(visit);
    accumulator_.forEachPlane(visit);
    filter_.forEachPlane(visit);
    taa_.forEachPlane(visit);
  }

  const Plane3& process(const FrameData& frame, const FrameData* previous, Plane3& /*out*/, FrameStats& stats) override {
    const AsvgfSettings& s = settings_;
    const svgf::FilterParams p = asvgf::filterParams(s);
    if (p.requiredPad() > filter_.pad() || asvgf::gradientPad(s.gradientIterations) > gradientPad_) {
      // More levels than allocated for: the settings changed.
      resizeHistory(frame.width, frame.height);
      resetHistory();
      previous = nullptr;
    }
    const auto* albedo = frame.has(Buffer::Albedo) ? &frame.planes(Buffer::Albedo) : nullptr;
    {
      PassTimer t(stats, "reproject");
      reproject(frame, previous, s.reprojection, reprojection_);
    }
    {
      PassTimer t(stats, "features");
      const bool reflected = s.reflectedNormals && frame.has(Buffer::ReflectedNormal);
      if (reflected) asvgf::guideNormals(frame.planes(Buffer::Normal), &frame.planes(Buffer::ReflectedNormal), normals_);
      guide_.build(frame.plane(Buffer::Depth), reflected ? normals_ : frame.planes(Buffer::Normal),
                   frame.has(Buffer::DepthGradient) ? &frame.planes(Buffer::DepthGradient) : nullptr, 0.0f);
    }
    {
      PassTimer t(stats, "demodulate");
      demodulate(frame.planes(Buffer::Color), albedo, demod_);
    }
    // The temporal gradient of each stratum, then its a-trous levels.
    const bool samples = s.gradientSource == AsvgfGradientSource::samples;
    if (samples) {
      PassTimer t(stats, "gradient");
      asvgf::gradientFromSamples(frame.plane(Buffer::GradientSample), frame.plane(Buffer::GradientPrevious),
                                 frame.plane(Buffer::GradientCurrent), guide_, s.antilagScale, gradient_);
    } else {
      // Not A-SVGF: last frame's moments against this frame (before they are accumulated).
      PassTimer t(stats, "antilag");
      asvgf::historyLuminances(reprojection_, demod_, accumulator_.moment1(), accumulator_.moment2(),
                               p.variance.luminance, guide_, gradient_);
    }
    {
      PassTimer t(stats, "gradientAtrous");
      asvgf::filterGradient(gradient_, s.gradientIterations, p.variance, !samples);
      if (!samples) asvgf::historyAntilagGradient(gradient_, s.antilagNoiseSigmas, s.antilagScale);
    }
    {
      PassTimer t(stats, "accumulate");
      AccumulationOptions opt;
      opt.luminance = p.variance.luminance;
      opt.temporalGradient = &gradient_.result;
      opt.temporalGradientStride = asvgf::kStratum;
      opt.historyExponent = s.historyExponent;
      accumulator_.run(reprojection_, demod_, s.minAlphaColor, s.minAlphaMoments, s.maxHistoryLength, opt);
    }
    const AtrousImage& filtered = filter_.run(guide_, accumulator_, demod_, nullptr, p, stats);
    {
      PassTimer t(stats, "remodulate");
      parallelRows(frame.height, [&](int y) {  // the padded filter output, remodulated row by row
        for (int c = 0; c < 3; ++c) std::copy_n(filtered.color[c].row(y), frame.width, result_[c].row(y));
        remodulateRow(result_, albedo, result_, y);
      });
    }
    if (!s.taa.taa) return result_;
    PassTimer t(stats, "taa+export");  // writes the output view (takeOutputRows)
    // The own-surface box's keys: object id (A-SVGF excludes no emitters).
    const bool keyed = s.taa.taaOwnSurface && taaSurfaceKeys(frame, nullptr, nullptr, taaKeys_);
    return taa_.run(reprojection_, result_, s.taa, keyed ? &taaKeys_ : nullptr, takeOutputRows());
  }

 private:
  Reprojection reprojection_;
  AtrousGuide guide_;
  std::vector<Plane> normals_;  // the filter's normals (reflected on mirror pixels)
  Plane3 demod_, result_;
  asvgf::GradientImage gradient_;
  int gradientPad_ = 0;
  TemporalAccumulator accumulator_;
  svgf::Filter filter_;
  Taa taa_;
  PixelVector<uint32_t> taaKeys_;  // TaaSettings::taaOwnSurface
};

}  // namespace

std::unique_ptr<Denoiser> createAsvgfCpu(tbb::task_arena& arena) { return std::make_unique<AsvgfCpu>(arena); }

}  // namespace rtd
