#if defined(RTD_HAS_VULKAN)
#include "methods/svgf/gersthofer_vulkan.h"

namespace rtd::svgf {

namespace {
uint32_t momentLuminanceMode(const FilterParams& p) { return uint32_t(p.variance.luminance); }
}  // namespace

void GpuGersthoferEye::resize(vk::Context& ctx, int w, int h) {
  width_ = w;
  height_ = h;
  reprojection_.allocate(ctx, w, h, 8);
  gradient_.allocate(ctx, w, h, 2);
  guideNormal_.allocate(ctx, w, h, 3);
  counter_.allocate(ctx, 2, 1, 1);
  boost_.allocate(ctx, w, h, 1);
  for (vk::Planes* p : {&currentComposite_, &currentIndirect_, &median_, &shared_, &output_, &fxaa_}) p->allocate(ctx, w, h, 3);
  composite_.resize(ctx, w, h);
  indirect_.resize(ctx, w, h);
  for (auto& d : distance_) d.allocate(ctx, w, h, 1);
  glossyCentre_.allocate(ctx, w, h, 1);
  glossyScale_.allocate(ctx, w, h, 1);
  source_.allocate(ctx, w, h, 6);
  post_.allocate(ctx, w, h, 4);
  filter_.resize(ctx, w, h);
  taa_.resize(w, h);
  reset();
}

void GpuGersthoferEye::reset() {
  composite_.reset();
  indirect_.reset();
  taa_.reset();
  distanceValid_ = false;
}

vk::Planes& GpuGersthoferEye::shared() {
  exchanged_ = true;
  return shared_;
}

void GpuGersthoferEye::front(vk::Recorder& rec, const vk::GpuFrame& frame, const vk::GpuFrame* previous,
                             const SvgfSettings& s) {
  const FilterParams params = filterParams(s, false);
  const int w = frame.width, h = frame.height;
  const vk::Planes* albedo = frame.has(Buffer::Albedo) ? &frame[Buffer::Albedo] : nullptr;
  const vk::Planes* mask = s.useSampleMask && frame.has(Buffer::SampleMask) ? &frame[Buffer::SampleMask] : nullptr;
  exchanged_ = false;
  const vk::Binding dummy(rec.context().dummy());
  rec.pass("reproject");
  vk::reproject(rec, frame, previous, s.reprojection, reprojection_);
  rec.pass("features");
  vk::atrousGuide(rec, frame, s.maxDepthSlope, gradient_);
  rec.pass("demodulate");
  vk::demodulate(rec, frame[Buffer::Color], albedo, currentComposite_);
  if (frame.has(Buffer::IndirectDiffuse)) vk::demodulate(rec, frame[Buffer::IndirectDiffuse], albedo, currentIndirect_);
  else rec.fill(currentIndirect_.buffer, 0);
  // Whether masking is on (the mask leaves pixels out) is known on the GPU only: the coverage
  // counts decide the boost's c and whether the median runs. An explicit maskCoverage decides
  // on the host.
  const bool measure = mask && !(s.maskCoverage > 0.0f);
  masked_ = mask && (measure || s.maskCoverage < 1.0f);
  if (measure) {
    struct CoveragePC {
      uint32_t width, height, hasHidden;
    } cpc{uint32_t(w), uint32_t(h), frame.has(Buffer::HiddenArea)};
    rec.fill(counter_.buffer, 0);
    rec.dispatch("gersthofer_coverage", {*mask, frame.bindingOf(Buffer::HiddenArea, rec.context()), counter_}, cpc, w, h);
  }
  boosted_ = masked_ && s.maskBoost;
  if (boosted_) {
    struct BoostPC {
      uint32_t width, height;
      float coverage;
    } bpc{uint32_t(w), uint32_t(h), s.maskCoverage};
    // Decided before the accumulation (the previous lengths are still the accumulator's
    // current ones), applied to this frame's filter input by the composite pass.
    rec.dispatch("gersthofer_boost", {reprojection_, composite_.current(), *mask, measure ? vk::Binding(counter_) : dummy, boost_},
                 bpc, w, h);
  }
  rec.pass("accumulate");
  const uint32_t lum = momentLuminanceMode(params);
  composite_.run(rec, reprojection_, currentComposite_, s.alphaColor, s.alphaMoments, s.maxHistoryLength, lum,
                 s.momentsTrueAverage, mask, nullptr, nullptr, !s.fixedAlpha);
  indirect_.run(rec, reprojection_, currentIndirect_, s.alphaColor, s.alphaMoments, s.maxHistoryLength, lum,
                s.momentsTrueAverage, mask, nullptr, nullptr, !s.fixedAlpha);
  if (s.glossyWeights && frame.has(Buffer::SecondaryDistance)) {
    struct DistancePC {
      uint32_t width, height;
      float alpha;
      uint32_t fixedAlpha, hasHistory, hasMask;
    } dpc{uint32_t(w), uint32_t(h), s.alphaColor, s.fixedAlpha, distanceValid_, mask != nullptr};
    const vk::Planes& prev = distance_[distanceCur_];
    distanceCur_ ^= 1;
    rec.dispatch("gersthofer_distance",
                 {reprojection_, frame[Buffer::SecondaryDistance], prev, composite_.current(),
                  mask ? vk::Binding(*mask) : dummy, distance_[distanceCur_]},
                 dpc, w, h);
    distanceValid_ = true;
  } else {
    distanceValid_ = false;
  }
  if (s.indirectDiffuseMedian && !(masked_ && !measure)) {
    // Off while masking: decided here where maskCoverage is given, by the counts otherwise.
    rec.pass("median");
    struct MedianPC {
      uint32_t width, height, hasRoughness, skipWhenMasked;
    } mpc{uint32_t(w), uint32_t(h), 0, measure};
    rec.dispatch("median3x3", {indirect_.current(), dummy, median_, measure ? vk::Binding(counter_) : dummy}, mpc, w, h);
    indirectDiffuse_ = &median_;
  } else {
    indirectDiffuse_ = &indirect_.current();
  }
}

const vk::Planes& GpuGersthoferEye::back(vk::Recorder& rec, const vk::GpuFrame& frame, const SvgfSettings& s,
                                         bool& emissionIncluded) {
  const FilterParams params = filterParams(s, false);
  const int w = frame.width, h = frame.height;
  const vk::Planes* albedo = frame.has(Buffer::Albedo) ? &frame[Buffer::Albedo] : nullptr;
  const vk::Binding dummy(rec.context().dummy());
  GpuFilterExtras extras;
  rec.pass("composite");
  const vk::Planes& diffuse = exchanged_ ? shared_ : *indirectDiffuse_;
  const bool split = &diffuse != &indirect_.current();
  if (split || boosted_) {
    struct PC {
      uint32_t width, height, flags;
    } pc{uint32_t(w), uint32_t(h), (split ? 1u : 0u) | (boosted_ ? 2u : 0u)};
    rec.dispatch("gersthofer_composite",
                 {composite_.current(), indirect_.current(), diffuse, boosted_ ? vk::Binding(boost_) : dummy, source_,
                  currentComposite_},
                 pc, w, h);
    extras.source = &source_;
  }
  if (s.spatialVarianceObjectId && frame.has(Buffer::ObjectId)) extras.objectId = &frame[Buffer::ObjectId];
  if (s.glossyWeights && frame.has(Buffer::Roughness)) {
    struct PC {
      uint32_t width, height, hasMetalness;
      float glossyMetalness;
    } pc{uint32_t(w), uint32_t(h), frame.has(Buffer::Metalness), s.glossyMetalness};
    rec.dispatch("gersthofer_glossy",
                 {frame[Buffer::Roughness], frame.bindingOf(Buffer::Metalness, rec.context()), glossyCentre_, glossyScale_},
                 pc, w, h);
    extras.centreScale = &glossyCentre_;
    if (distanceValid_) {
      extras.indirectDistance = &distance_[distanceCur_];
      extras.indirectDistanceScale = &glossyScale_;
    }
  }
  // Issue 12: emitter pixels weigh 0 as neighbours (a zero guide normal).
  const vk::Planes& normal = vk::emitterGuideNormal(rec, frame, s.emitters, guideNormal_);
  const vk::Planes& r = filter_.run(rec, frame[Buffer::Depth], normal, gradient_, composite_,
                                     currentComposite_, nullptr, params, "", extras);
  rec.pass("remodulate");
  vk::remodulate(rec, r, albedo, output_);
  const vk::Planes* shown = &output_;
  if (s.taa.taa) {
    rec.pass("taa");
    shown = &taa_.run(rec, reprojection_, output_, s.taa);
  }
  const bool hidden = frame.has(Buffer::HiddenArea);
  emissionIncluded = false;
  if (!s.fxaa && s.toneMap == SvgfToneMap::none && !hidden) return *shown;
  rec.pass("postprocess");
  struct PostPC {
    uint32_t width, height, hasEmission;
  } ppc{uint32_t(w), uint32_t(h), frame.has(Buffer::Emission)};
  rec.dispatch("gersthofer_post", {*shown, frame.bindingOf(Buffer::Emission, rec.context()), post_}, ppc, w, h);
  emissionIncluded = true;
  vk::Planes* result = &post_;
  if (s.fxaa) {
    vk::fxaa(rec, post_, fxaa_);
    result = &fxaa_;
  }
  struct FinishPC {
    uint32_t width, height, aces, hasHidden;
  } fpc{uint32_t(w), uint32_t(h), s.toneMap == SvgfToneMap::aces, hidden};
  if (fpc.aces || fpc.hasHidden)
    rec.dispatch("gersthofer_finish", {*result, frame.bindingOf(Buffer::HiddenArea, rec.context())}, fpc, w, h);
  return *result;
}

std::vector<MemoryUse> GpuGersthoferEye::memory() const {
  const uint64_t history =
      composite_.bytes() + indirect_.bytes() + distance_[0].buffer.size() + distance_[1].buffer.size() + taa_.bytes();
  uint64_t intermediate = filter_.bytes();
  for (const vk::Planes* p : {&reprojection_, &gradient_, &guideNormal_, &counter_, &currentComposite_, &currentIndirect_,
                              &glossyCentre_, &glossyScale_, &median_, &shared_, &source_, &output_, &post_, &fxaa_, &boost_})
    intermediate += p->buffer.size();
  return {{"history", history}, {"intermediate", intermediate}};
}

}  // namespace rtd::svgf
#endif
