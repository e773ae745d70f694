#include "methods/svgf/gersthofer.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/parallel.h"
#include "core/timer.h"
#include "methods/svgf/svgf_passes.h"
#include "passes/demodulation.h"
#include "passes/emitters.h"
#include "passes/fxaa.h"

namespace rtd::svgf {

namespace {
void copyPadded(const Plane& in, PaddedPlane& out) { out.copyFrom(in); }
}  // namespace

size_t boostDisoccluded(const Reprojection& rp, const Plane& previousLength, const Plane& mask, float c, Plane& factor) {
  const float k = 1.0f / c;
  std::atomic<size_t> count{0};
  parallelRows(mask.height, [&](int y) {
    size_t n = 0;
    float* f = factor.row(y);
    for (int x = 0; x < mask.width; ++x) {
      const size_t i = size_t(y) * mask.width + x;
      // "for which reprojection failed": no valid tap, or taps that hold no data yet.
      const bool boost = mask.data[i] != 0.0f &&
                         (rp.kind[i] == Reprojection::None || std::round(rp.gather(previousLength, i)) < 1.0f);
      f[x] = boost ? k : 1.0f;
      n += boost;
    }
    count += n;
  });
  return count.load();
}

void GersthoferEye::resize(int w, int h, int pad) {
  width_ = w;
  height_ = h;
  reprojection_.resize(w, h);
  guide_.resize(w, h, pad);
  for (PaddedPlane* p : {&objectId_, &indirectDistance_, &indirectDistanceScale_, &centreScale_}) p->resize(w, h, pad);
  for (Plane3* p : {&currentComposite_, &currentIndirect_, &median_, &shared_, &input_, &output_, &post_})
    rtd::resize(*p, w, h);
  composite_.resize(w, h);
  indirect_.resize(w, h);
  for (auto& d : distance_) d.resize(w, h);
  luma_.resize(w, h);
  boost_.resize(w, h);
  filter_.resize(w, h, pad);
  taa_.resize(w, h);  // its planes allocated when TAA first runs
}

void GersthoferEye::reset() {
  composite_.reset();
  indirect_.reset();
  taa_.reset();
  distanceValid_ = false;
}

void GersthoferEye::front(const FrameData& frame, const FrameData* previous, const SvgfSettings& s, FrameStats& stats) {
  const FilterParams params = filterParams(s, false);
  if (frame.width != width_ || frame.height != height_ || params.requiredPad() > filter_.pad()) {
    resize(frame.width, frame.height, params.requiredPad());
    reset();
    previous = nullptr;
  }
  const std::vector<Plane>* albedo = frame.has(Buffer::Albedo) ? &frame.planes(Buffer::Albedo) : nullptr;
  const Plane* mask = s.useSampleMask && frame.has(Buffer::SampleMask) ? &frame.plane(Buffer::SampleMask) : nullptr;
  const Plane* hidden = frame.has(Buffer::HiddenArea) ? &frame.plane(Buffer::HiddenArea) : nullptr;
  // Masking is on where the frame has a sample mask that leaves pixels out (a renderer may
  // write an all-ones mask for fully traced frames).
  const float coverage = !mask ? 1.0f : s.maskCoverage > 0.0f ? s.maskCoverage : sampleCoverage(*mask, hidden);
  masked_ = mask && coverage < 1.0f;
  exchanged_ = false;
  {
    PassTimer t(stats, "reproject");
    reproject(frame, previous, s.reprojection, reprojection_);
  }
  {
    PassTimer t(stats, "features");
    guide_.build(frame.plane(Buffer::Depth), frame.planes(Buffer::Normal),
                 frame.has(Buffer::DepthGradient) ? &frame.planes(Buffer::DepthGradient) : nullptr, s.maxDepthSlope);
    excludeEmitters(frame, s.emitters, guide_);  // issue 12: emitter pixels weigh 0 as neighbours
  }
  {
    PassTimer t(stats, "demodulate");
    demodulate(frame.planes(Buffer::Color), albedo, currentComposite_);
    if (frame.has(Buffer::IndirectDiffuse)) {
      demodulate(frame.planes(Buffer::IndirectDiffuse), albedo, currentIndirect_);
    } else {
      // No split: everything counts as "direct + indirect specular" (nothing to share).
      for (auto& p : currentIndirect_) p.fill(0.0f);
    }
    // Eq. 3.1, decided before the accumulation (the previous lengths are still the
    // accumulators' current ones) and applied to this frame's filter input in back().
    boosted_ = masked_ && s.maskBoost && coverage > 0.0f &&
               boostDisoccluded(reprojection_, composite_.historyLength(), *mask, coverage, boost_) > 0;
  }
  {
    PassTimer t(stats, "accumulate");
    AccumulationOptions opt;
    opt.luminance = params.variance.luminance;
    opt.cumulativeMoments = s.momentsTrueAverage;
    opt.cumulativeColor = !s.fixedAlpha;
    opt.sampleMask = mask;
    composite_.run(reprojection_, currentComposite_, s.alphaColor, s.alphaMoments, s.maxHistoryLength, opt);
    opt.moments = false;  // the variance is the composite's
    indirect_.run(reprojection_, currentIndirect_, s.alphaColor, s.alphaMoments, s.maxHistoryLength, opt);
    if (s.glossyWeights && frame.has(Buffer::SecondaryDistance)) accumulateDistance(frame, mask, s);
    else distanceValid_ = false;
  }
  if (s.indirectDiffuseMedian && !masked_) {
    // Sec. 3.4.2, "disabled if masking is enabled": sampled pixels would face black or boosted
    // neighbours only.
    PassTimer t(stats, "median");
    median3x3(indirect_.color(), nullptr, median_);
    indirectDiffuse_ = &median_;
  } else {
    indirectDiffuse_ = &indirect_.color();
  }
}

// The indirect ray length z_i of w_zi, accumulated with the colour's weights and taps.
void GersthoferEye::accumulateDistance(const FrameData& frame, const Plane* mask, const SvgfSettings& s) {
  const Plane& current = frame.plane(Buffer::SecondaryDistance);
  const Plane& length = composite_.historyLength();  // this frame's n
  const bool history = distanceValid_;
  const Plane& prev = distance_[distanceCur_];
  distanceCur_ ^= 1;
  Plane& out = distance_[distanceCur_];
  const float alpha = s.alphaColor;
  parallelRows(height_, [&](int y) {
    for (int x = 0; x < width_; ++x) {
      const size_t i = size_t(y) * width_ + x;
      const float hist = history ? reprojection_.gather(prev, i) : 0.0f;
      if (mask && mask->data[i] == 0.0f) {
        out.data[i] = hist;  // no sample: the history carries over (0 where there is none)
        continue;
      }
      const float n = history ? length.data[i] : 1.0f;
      const float a = s.fixedAlpha ? (n <= 1.0f ? 1.0f : alpha) : newSampleWeight(n, alpha);
      out.data[i] = a * current.data[i] + (1.0f - a) * hist;
    }
  });
  distanceValid_ = true;
}

Plane3& GersthoferEye::shared() {
  exchanged_ = true;
  return shared_;
}

const Plane3& GersthoferEye::back(const FrameData& frame, const SvgfSettings& s, FrameStats& stats, bool& emissionIncluded) {
  const FilterParams params = filterParams(s, false);
  const std::vector<Plane>* albedo = frame.has(Buffer::Albedo) ? &frame.planes(Buffer::Albedo) : nullptr;
  FilterExtras extras;
  {
    PassTimer t(stats, "composite");
    // (direct + indirect specular) + indirect diffuse; the first is the accumulated composite
    // minus the accumulated indirect diffuse (the same weights and taps made both). Sampled
    // pixels without history then take Eq. 3.1's 1/c: "distributed to neighboring pixels
    // through ... spatial filtering"; kept out of the history, where it would stay 1/c too
    // bright until the EMA forgot it (a pixel is sampled once every 1/c frames).
    const Plane3& diffuse = exchanged_ ? shared_ : *indirectDiffuse_;
    const bool split = &diffuse != &indirect_.color();
    if (split || boosted_) {
      const Plane3& c = composite_.color();
      const Plane3& b = indirect_.color();
      parallelRows(height_, [&](int y) {
        const float* k = boosted_ ? boost_.row(y) : nullptr;
        for (int ch = 0; ch < 3; ++ch) {
          const float *pc = c[ch].row(y), *pb = b[ch].row(y), *pd = diffuse[ch].row(y);
          float* o = input_[ch].row(y);
          float* cur = currentComposite_[ch].row(y);
          for (int x = 0; x < width_; ++x) {
            const float v = split ? std::max(0.0f, pc[x] - pb[x]) + pd[x] : pc[x];
            o[x] = k ? v * k[x] : v;
            if (k) cur[x] *= k[x];  // the sample the spatial variance estimate sees, likewise
          }
        }
      });
      extras.input = &input_;
    }
    if (s.spatialVarianceObjectId && frame.has(Buffer::ObjectId)) {
      copyPadded(frame.plane(Buffer::ObjectId), objectId_);
      extras.objectId = &objectId_;
    }
    if (s.glossyWeights && frame.has(Buffer::Roughness)) {
      // w_r = 0.01 + sqrt(r) on the neighbours of glossy pixels, as 1/w_r on the centre;
      // w_zi's factor (1 - r(p)) where the indirect ray length is known.
      const Plane& r = frame.plane(Buffer::Roughness);
      const Plane* metal = frame.has(Buffer::Metalness) ? &frame.plane(Buffer::Metalness) : nullptr;
      const bool distance = distanceValid_;
      if (distance) copyPadded(distance_[distanceCur_], indirectDistance_);
      parallelRows(height_, [&](int y) {
        const float* pr = r.row(y);
        const float* pm = metal ? metal->row(y) : nullptr;
        float* cs = centreScale_.row(y);
        float* zs = indirectDistanceScale_.row(y);
        for (int x = 0; x < width_; ++x) {
          const bool glossy = !pm || pm[x] >= s.glossyMetalness;
          cs[x] = glossy ? 1.0f / roughnessWeight(pr[x]) : 1.0f;
          zs[x] = 1.0f - std::clamp(pr[x], 0.0f, 1.0f);
        }
      });
      extras.centreScale = &centreScale_;
      if (distance) {
        extras.indirectDistance = &indirectDistance_;
        extras.indirectDistanceScale = &indirectDistanceScale_;
      }
    }
  }
  // Empty pixels without history enter the filter as black samples (Gersthofer Sec. 3.3.1, Fig.
  // 5.8: "empty pixels ... considered as valid samples during filtering"), which the 1/c boost
  // compensates; Dundr's hole filling (a mask given to the filter) is not his.
  const AtrousImage& r = filter_.run(guide_, composite_, currentComposite_, nullptr, params, stats, "", extras);
  {
    PassTimer t(stats, "remodulate");
    for (int k = 0; k < 3; ++k) r.color[k].copyTo(output_[k]);
    remodulate(output_, albedo);
  }
  const Plane3* shown = &output_;
  if (s.taa.taa) {
    PassTimer t(stats, "taa");
    shown = &taa_.run(reprojection_, output_, s.taa);
  }
  const Plane* hidden = frame.has(Buffer::HiddenArea) ? &frame.plane(Buffer::HiddenArea) : nullptr;
  emissionIncluded = false;
  if (!s.fxaa && s.toneMap == SvgfToneMap::none && !hidden) return *shown;
  // Post-processing works on the final image, emitters included (they are added back here).
  PassTimer t(stats, "postprocess");
  const std::vector<Plane>* emission = frame.has(Buffer::Emission) ? &frame.planes(Buffer::Emission) : nullptr;
  parallelRows(height_, [&](int y) {
    for (int k = 0; k < 3; ++k) {
      const float* in = (*shown)[k].row(y);
      const float* e = emission ? (*emission)[k].row(y) : nullptr;
      float* o = post_[k].row(y);
      for (int x = 0; x < width_; ++x) o[x] = e ? in[x] + e[x] : in[x];
    }
  });
  emissionIncluded = true;
  Plane3* result = &post_;
  if (s.fxaa) {
    fxaa(post_, FxaaParams{}, luma_, output_);  // output_ is free again (TAA, if any, has its copy)
    result = &output_;
  }
  if (s.toneMap == SvgfToneMap::aces) toneMapAces(*result);
  if (hidden)
    parallelRows(height_, [&](int y) {
      const float* m = hidden->row(y);
      for (auto& p : *result) {
        float* o = p.row(y);
        for (int x = 0; x < width_; ++x)
          if (m[x] > 0.5f) o[x] = 0.0f;
      }
    });
  return *result;
}

void GersthoferEye::visitHistory(const PlaneVisitor& visit) const {
  composite_.forEachPlane(visit);
  indirect_.forEachPlane(visit);
  for (const Plane& d : distance_) visitPlane(visit, "indirect ray length", d);
  taa_.forEachPlane(visit);
}

void GersthoferEye::visitIntermediate(const PlaneVisitor& visit) const {
  reprojection_.forEachPlane(visit);
  guide_.forEachPlane(visit);
  for (const PaddedPlane* p : {&objectId_, &indirectDistance_, &indirectDistanceScale_, &centreScale_})
    p->visit(visit, "gersthofer guide");
  for (const Plane3* p : {&currentComposite_, &currentIndirect_, &median_, &shared_, &input_, &output_, &post_})
    visitPlanes(visit, "gersthofer image", *p);
  visitPlane(visit, "fxaa luma", luma_);
  visitPlane(visit, "boost", boost_);
  filter_.forEachPlane(visit);
}

std::vector<MemoryUse> GersthoferEye::memory() const {
  uint64_t history = 0, intermediate = 0;
  visitHistory([&](std::string_view, const float*, size_t n) { history += n * sizeof(float); });
  visitIntermediate([&](std::string_view, const float*, size_t n) { intermediate += n * sizeof(float); });
  // The reprojection's integer arrays (kinds, taps, masks) are not float planes.
  intermediate += uint64_t(reprojection_.kind.size()) * (sizeof(uint8_t) + sizeof(int32_t) + sizeof(uint16_t));
  return {{"history", history}, {"intermediate", intermediate}};
}

std::array<size_t, 2> exchangeIndirectDiffuse(GersthoferEye& left, const FrameData& lf, GersthoferEye& right,
                                              const FrameData& rf, const SvgfSettings& s) {
  EyeGuide gl = EyeGuide::of(lf), gr = EyeGuide::of(rf);
  gl.valid = &left.historyLength();  // taps must hold light: sampled now or accumulated before
  gr.valid = &right.historyLength();
  const size_t nl = eyeReproject(gl, gr, s.reprojection, s.eyeBlend, left.indirectDiffuse(), right.indirectDiffuse(),
                                 left.shared());
  const size_t nr = eyeReproject(gr, gl, s.reprojection, s.eyeBlend, right.indirectDiffuse(), left.indirectDiffuse(),
                                 right.shared());
  return {nl, nr};
}


}  // namespace rtd::svgf
