// Method "svgf": spatiotemporal variance-guided filtering (Schied et al. 2017) and the
// variants of Dundr, Gersthofer and Voorhuis as settings. Per radiance stream: demodulate,
// accumulate colour and luminance moments, estimate the variance, filter with the a-trous
// wavelet (feeding one level back as colour history); then sum the streams, remodulate and
// apply TAA. docs/methods/svgf.md has the details.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>

#include "backend/cpu/cpu_denoiser.h"
#include "core/parallel.h"
#include "methods/svgf/gersthofer.h"
#include "methods/svgf/svgf_filter.h"
#include "methods/svgf/svgf_passes.h"
#include "methods/svgf/svgf_reflections.h"
#include "passes/demodulation.h"
#include "passes/emitters.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "passes/taa_keys.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/svgf.h"

namespace rtd {

namespace {

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
    reflections_.resize(w, h, pad);
    filter_.resize(w, h, pad);
    // A stream's planes are allocated when a frame first has the stream (chooseStreams), the
    // median's when it runs: one-stream input keeps no second history (55 MB at 1280x720).
    for (auto& s : streams_) s = Stream{};
    rtd::resize(sum_, w, h);
    display_ = {};
    lobeMedian_ = {};
    taa_.resize(w, h);
  }
  void resetHistory() override {
    for (auto& s : streams_) s.accumulator.reset();
    reflections_.reset();
    taa_.reset();
    if (gersthofer_) gersthofer_->reset();
  }
  void visitMethodPlanes(const PlaneVisitor& visit) const override {
    reprojection_.forEachPlane(visit);
    guide_.forEachPlane(visit);
    filter_.forEachPlane(visit);
    reflections_.forEachPlane(visit);
    for (const auto& st : streams_) {
      visitPlanes(visit, "demodulated", st.demod);
      st.accumulator.forEachPlane(visit);
    }
    visitPlanes(visit, "sum", sum_);
    visitPlanes(visit, "display", display_);
    visitPlanes(visit, "diffuse lobe median", lobeMedian_);
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
    const bool lobes = nStreams == 2 && streams_[1].plan.lobe == svgf::Lobe::specular;
    // Before any history is touched: an explicitly requested part without its buffers throws.
    svgf::ReflectionParts parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return frame.has(b); }, lobes);
    // A mask without holes is no mask. The renderer writes a mask of ones at 1 spp; progressive
    // mode (Dundr Sec. 5) then computes exactly what the plain pipeline does (no pixel keeps an
    // unsampled history, every pixel is valid at every a-trous level, the fed-back level is
    // taken everywhere), only slower: the levels' validity weights cost ~1.14x.
    const Plane* mask = s.useSampleMask && frame.has(Buffer::SampleMask) ? &frame.plane(Buffer::SampleMask) : nullptr;
    mask_ = mask && svgf::sampleCoverage(*mask, nullptr) < 1.0f ? mask : nullptr;
    const auto* albedo = frame.has(Buffer::Albedo) ? &frame.planes(Buffer::Albedo) : nullptr;
    {
      // The guide's rows right after the reprojection's (both read the frame's depth and
      // normals: the second reads them from cache; ~0.3 ms of a 1280x720 frame).
      PassTimer t(stats, "reproject+features");
      const std::vector<Plane>* gradient = frame.has(Buffer::DepthGradient) ? &frame.planes(Buffer::DepthGradient) : nullptr;
      reproject(frame, previous, s.reprojection, reprojection_, [&](int rowBegin, int rowEnd) {
        guide_.buildRows(frame.plane(Buffer::Depth), frame.planes(Buffer::Normal), gradient, s.maxDepthSlope, rowBegin, rowEnd);
      });
      excludeEmitters(frame, s.emitters, guide_);  // issue 12: emitter pixels weigh 0 as neighbours
    }
    {
      // Without parts too: it records that this frame has none (stream(), clipBoxes() and
      // taaMotion() read them; a previous frame's, before a change of settings, would be stale).
      std::optional<PassTimer> t;
      if (parts.classes) t.emplace(stats, "reflections");  // Voorhuis: classes, diamond search, reflected features
      reflections_.prepare(frame, previous, s, parts, lobes, reprojection_);
    }
    bool remodulated = false;
    for (int k = 0; k < nStreams; ++k) {
      Stream& st = streams_[k];
      const std::string suffix = nStreams > 1 ? std::string(".") + st.plan.name : std::string();
      if (!st.plan.filtered) {  // components = diffuse: the specular lobe as it comes
        PassTimer t(stats, "sum" + suffix);
        const std::vector<Plane>& raw = frame.planes(st.plan.buffer);
        addStream([&](int c, int y) { return raw[c].row(y); }, k == 0, nullptr, albedo);
        continue;
      }
      const svgf::Reflections::StreamInputs in = reflections_.stream(frame, st.plan, reprojection_, guide_, k);
      // One stream in the albedo of the frame and nothing between the sum and the remodulation
      // (no median): the filter writes sum_ remodulated, from its last a-trous level where it
      // can (AtrousLevel::remodulatedOut), so no pass reads the level back.
      const bool intoSum = nStreams == 1 && !s.fireflyMedian && in.albedo == albedo;
      const AtrousImage& result = filterStream(frame, st, in, suffix, stats, albedo, intoSum);
      if (intoSum) {
        remodulated = true;
        continue;
      }
      if (s.fireflyMedian && st.plan.lobe == svgf::Lobe::diffuse) {
        // With the lobes split, the median takes the diffuse lobe only, everywhere: it holds
        // no specular highlights (Voorhuis Sec. 6: "only ... pixels that have a diffuse
        // primary hit", so that highlights survive), and is taken before any other colour
        // scales it.
        {
          PassTimer t(stats, "median" + suffix);
          allocateOnce(display_, frame.width, frame.height);
          allocateOnce(lobeMedian_, frame.width, frame.height);
          for (int c = 0; c < 3; ++c) result.color[c].copyTo(display_[c]);
          svgf::median3x3(display_, nullptr, lobeMedian_);
        }
        PassTimer t(stats, "sum" + suffix);
        addStream([&](int c, int y) { return lobeMedian_[c].row(y); }, k == 0, in.albedo, albedo);
        continue;
      }
      PassTimer t(stats, "sum" + suffix);
      addStream([&](int c, int y) { return result.color[c].row(y); }, k == 0, in.albedo, albedo);
    }
    stats.notes = std::move(parts.notes);
    Plane3* shown = &sum_;
    if (s.fireflyMedian && !lobes) {
      PassTimer t(stats, "median");
      allocateOnce(display_, frame.width, frame.height);
      svgf::median3x3(sum_, frame.has(Buffer::Roughness) ? &frame.plane(Buffer::Roughness) : nullptr, display_);
      shown = &display_;
    }
    if (!remodulated) {
      PassTimer t(stats, "remodulate");
      remodulate(*shown, albedo);
    }
    if (!s.taa.taa) return *shown;
    // The own-surface box's keys: object id, the Voorhuis classes where they were computed,
    // the emitters excludeEmitters() took out of the filter.
    bool keyed = false;
    if (s.taa.taaOwnSurface) {
      PassTimer t(stats, "taa keys");
      keyed = taaSurfaceKeys(frame, &s.emitters, parts.classes ? &reflections_.classes() : nullptr, taaKeys_);
    }
    PassTimer t(stats, "taa+export");  // writes the output view (takeOutputRows)
    return taa_.run(reflections_.taaMotion(frame, reprojection_, s.taaGlossyReflectionMotion, s.taaMirrorHistory), *shown, s.taa,
                    keyed ? &taaKeys_ : nullptr, takeOutputRows());
  }

 private:
  int requiredPad() const { return svgf::filterParams(settings_, false).requiredPad(); }

  // Gersthofer's pipeline (gersthofer.h) for one view; a StereoDenoiser runs two of them.
  const Plane3& gersthofer(const FrameData& frame, const FrameData* previous, FrameStats& stats) {
    if (!gersthofer_) gersthofer_ = std::make_unique<svgf::GersthoferEye>();
    gersthofer_->front(frame, previous, settings_, stats);
    const Plane3& result = gersthofer_->back(frame, settings_, stats, resultHasEmission_);
    stats.memory = gersthofer_->memory();
    stats.memory.push_back({"frames", current_.bytes() + previous_.bytes()});
    return result;
  }

  // Which streams this frame has, per the `components` setting.
  int chooseStreams(const FrameData& f) {
    svgf::StreamPlan plan[2];
    const int n = svgf::planStreams(settings_.components, [&](Buffer b) { return f.has(b); }, plan, settings_.preferLobes);
    for (int k = 0; k < n; ++k) {
      Stream& st = streams_[k];
      if (st.plan.buffer != plan[k].buffer) st.accumulator.reset();  // another stream's history is meaningless
      st.plan = plan[k];
      if (st.demod[0].empty()) {  // the first frame with a k-th stream at this size (resizeHistory)
        rtd::resize(st.demod, f.width, f.height);
        st.accumulator.resize(f.width, f.height);
      }
    }
    return n;
  }

  // Demodulate and accumulate one stream, then the shared SVGF filter (variance, a-trous
  // levels, feedback); returns the filtered image. `in`: the stream's reprojection, guide and
  // demodulation colour, and the Voorhuis per-pixel inputs (svgf::Reflections::stream).
  // `intoSum`: the result goes to sum_ instead, remodulated by `albedo` (null: as it is).
  const AtrousImage& filterStream(const FrameData& frame, Stream& st, const svgf::Reflections::StreamInputs& in,
                                  const std::string& suffix, FrameStats& stats, const std::vector<Plane>* albedo = nullptr,
                                  bool intoSum = false) {
    const SvgfSettings& s = settings_;
    const svgf::FilterParams p = svgf::filterParams(s, st.plan.indirect);
    const std::vector<Plane>& radiance = frame.planes(st.plan.buffer);
    AccumulationOptions opt;
    std::atomic<size_t> shortCount{0};  // the fused variance rows' short-history pixels
    // The clip boxes are taken over the demodulated frame before the blend (Voorhuis Sec.
    // 4.2.3), so it is demodulated first; otherwise the accumulation demodulates on the fly
    // and stores the demodulated frame for the variance pass in the same pass.
    const bool clipping = reflections_.parts().clipping;
    if (clipping) {
      {
        PassTimer t(stats, "demodulate" + suffix);
        demodulate(radiance, in.albedo, st.demod);
      }
      PassTimer t(stats, "clip" + suffix);
      reflections_.clipBoxes(st.demod, st.plan, s, opt.clipLow, opt.clipHigh);
    }
    {
      PassTimer t(stats, (clipping ? "accumulate" : "demodulate+accumulate") + std::string("+variance rows") + suffix);
      opt.luminance = p.variance.luminance;
      opt.cumulativeMoments = s.momentsTrueAverage;
      opt.sampleMask = mask_;
      opt.alphaPlane = in.alpha;
      // The variance pass's rows right after each chunk of accumulated rows (Filter::varianceRows).
      opt.afterRows = [&](int rowBegin, int rowEnd) {
        shortCount += filter_.varianceRows(st.accumulator, st.demod, p, rowBegin, rowEnd);
      };
      if (clipping) {
        st.accumulator.run(*in.reprojection, st.demod, s.alphaColor, s.alphaMoments, s.maxHistoryLength, opt);
      } else {
        opt.albedo = in.albedo;
        opt.current = &st.demod;
        st.accumulator.run(*in.reprojection, radiance, s.alphaColor, s.alphaMoments, s.maxHistoryLength, opt);
      }
    }
    svgf::FilterParams fp = p;
    fp.spatialFalloff = in.falloff;  // Voorhuis Eq. 6
    fp.surfaceKey = in.surfaceKey;   // Sec. 4.1: the reflected guide's mirror pixels apart
    const size_t rowsShortCount = shortCount;
    svgf::FilterExtras extras;
    extras.varianceRowsShortCount = &rowsShortCount;
    if (intoSum) {  // the result in sum_, remodulated by `albedo`
      extras.remodulatedOut = &sum_;
      extras.remodulateAlbedo = albedo;
    }
    return filter_.run(*in.guide, st.accumulator, st.demod, mask_, fp, stats, suffix, extras);
  }

  // sum_ (+)= this stream's filtered illumination, remodulated by the stream's own colour
  // `streamAlbedo` (null: not demodulated) and divided by `albedo`, so that the shared
  // remodulation by `albedo` restores it exactly.
  // `rows(c, y)`: row y of channel c of the stream's filtered illumination.
  template <class Rows>
  void addStream(Rows&& rows, bool first, const std::vector<Plane>* streamAlbedo, const std::vector<Plane>* albedo) {
    const int w = sum_[0].width;
    const bool same = streamAlbedo == albedo;  // the common case: nothing to convert
    const std::vector<Plane>* times = same ? nullptr : streamAlbedo;
    const std::vector<Plane>* divide = same ? nullptr : albedo;
    parallelRows(sum_[0].height, [&](int y) {
      for (int c = 0; c < 3; ++c) {
        const float* in = rows(c, y);
        float* o = sum_[c].row(y);
        const float* m = times ? (*times)[c].row(y) : nullptr;
        const float* a = divide ? (*divide)[c].row(y) : nullptr;
        if (!m && !a) {  // the common case, as loops that vectorize
          if (first) std::copy(in, in + w, o);
          else for (int x = 0; x < w; ++x) o[x] += in[x];
          continue;
        }
        for (int x = 0; x < w; ++x) {
          float v = in[x];
          if (m) v *= demodulationFactor(m[x]);
          if (a) v /= demodulationFactor(a[x]);
          o[x] = first ? v : o[x] + v;
        }
      }
    });
  }

  Reprojection reprojection_;
  AtrousGuide guide_;
  svgf::Reflections reflections_;
  svgf::Filter filter_;
  const Plane* mask_ = nullptr;
  Stream streams_[svgf::kMaxStreams];
  Plane3 sum_, display_, lobeMedian_;
  Taa taa_;
  PixelVector<uint32_t> taaKeys_;  // TaaSettings::taaOwnSurface
  std::unique_ptr<svgf::GersthoferEye> gersthofer_;  // components = composite
};

}  // namespace

std::unique_ptr<Denoiser> createSvgfCpu(tbb::task_arena& arena) { return std::make_unique<SvgfCpu>(arena); }

}  // namespace rtd
