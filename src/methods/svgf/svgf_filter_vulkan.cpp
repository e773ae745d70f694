#if defined(RTD_HAS_VULKAN)
#include "methods/svgf/svgf_filter_vulkan.h"

namespace rtd::svgf {

void GpuFilter::resize(vk::Context& ctx, int w, int h) {
  for (auto& l : levels_) l.allocate(ctx, w, h, 5);
  sigmaScale_.allocate(ctx, w, h, 1);
  // As the CPU's Filter: what only some settings use, when they first run.
  prefilteredVariance_ = {};
  for (auto& v : valid_) v = {};
}

uint64_t GpuFilter::bytes() const {
  uint64_t n = sigmaScale_.buffer.size() + prefilteredVariance_.buffer.size();
  for (const auto& l : levels_) n += l.buffer.size();
  for (const auto& v : valid_) n += v.buffer.size();
  return n;
}

const vk::Planes& GpuFilter::run(vk::Recorder& rec, const vk::Planes& depth, const vk::Planes& normal,
                                 const vk::Planes& gradient, vk::GpuTemporalAccumulator& acc,
                                 const vk::Planes& current, const vk::Planes* mask, const FilterParams& p,
                                 const std::string& suffix, const GpuFilterExtras& extras) {
  const vk::Planes& source = extras.source ? *extras.source : acc.current();
  const int width = current.width, height = current.height;
  const uint32_t lum = uint32_t(p.variance.luminance);
  const size_t planeBytes = size_t(width) * height * 4;
  rec.pass("variance" + suffix);
  {
    const VarianceParams& v = p.variance;
    struct PC {
      uint32_t width, height;
      float shortHistoryFrames;
      int32_t radius;
      float sigmaDepth, depthEpsilon;
      int32_t normalExponent;
      uint32_t luminanceMode, flags;
      float depthEpsilonRelative;
    } pc{uint32_t(width), uint32_t(height), float(v.shortHistoryFrames), v.radius, v.sigmaDepth, v.depthEpsilon,
         v.normalExponent, lum, 0, v.depthEpsilonRelative};
    if (v.shortHistory == SvgfShortHistory::spatialEstimate && v.shortHistoryFrames > 0) pc.flags |= 1;
    if (v.fromMoments) pc.flags |= 2;
    if (v.shortHistory == SvgfShortHistory::disableLuminanceWeight) pc.flags |= 4;
    if (p.shortHistoryBandwidth) pc.flags |= 8;
    const vk::Planes* key = extras.objectId ? extras.objectId : extras.surfaceKey;
    if (key) pc.flags |= 16;
    rec.dispatch("svgf_variance",
                 {depth, normal, gradient, source, current, levels_[0], sigmaScale_,
                  key ? vk::Binding(*key) : vk::Binding(rec.context().dummy())},
                 pc, width, height);
    if (p.variancePrefilter == SvgfVariancePrefilter::once) {
      vk::allocateOnce(prefilteredVariance_, rec.context(), width, height, 1);
      vk::gaussian3x3(rec, levels_[0], 4, prefilteredVariance_, 0);
      rec.copy(prefilteredVariance_.buffer, levels_[0].buffer, planeBytes, 0, 4 * planeBytes);
    }
  }
  const int n = p.iterations;
  int steps[8];
  levelSteps(p.levelOrder, n, steps);
  int cur = 0;
  if (mask)
    for (auto& v : valid_) vk::allocateOnce(v, rec.context(), width, height, 1);
  for (int i = 0; i < n; ++i) {
    rec.pass("atrous" + std::to_string(i + 1) + suffix);
    vk::GpuAtrousLevel lv;
    lv.radius = p.kernel == SvgfKernel::b3spline5x5 ? 2 : 1;
    lv.step = steps[i];
    lv.sigmaDepth = p.variance.sigmaDepth;
    lv.depthEpsilon = p.variance.depthEpsilon;
    lv.depthEpsilonRelative = p.variance.depthEpsilonRelative;
    lv.normalExponent = p.variance.normalExponent;
    lv.sigmaLuminance = p.sigmaLuminance;
    lv.luminanceEpsilon = p.luminanceEpsilon;
    lv.prefilterVariance = p.variancePrefilter == SvgfVariancePrefilter::everyLevel;
    lv.varianceScale = p.luminanceScale == SvgfLuminanceScale::variance;
    lv.sigmaScale = &sigmaScale_;
    lv.propagateVariance = p.propagateVariance && i + 1 < n;  // the last level's variance is not used
    lv.luminanceMode = lum;
    lv.indirectDistance = extras.indirectDistance;
    lv.indirectDistanceScale = extras.indirectDistanceScale;
    lv.centreScale = extras.centreScale;
    if (mask) {
      // Level-0 validity is historyLength > 0 (the CPU's markValid), read straight from the
      // accumulator's length plane; later levels read the previous level's validity.
      if (i == 0) {
        lv.validIn = &acc.current();
        lv.validInPlane = 5;
      } else {
        lv.validIn = &valid_[(i - 1) & 1];
      }
      lv.validOut = &valid_[i & 1];
    }
    lv.spatialFalloff = extras.spatialFalloff;
    lv.surfaceKey = extras.surfaceKey;
    vk::atrousLevel(rec, depth, normal, gradient, lv, levels_[cur], levels_[cur ^ 1]);
    cur ^= 1;
    // The feedback level's output becomes next frame's colour history (Schied Sec. 4.3).
    if (i + 1 == p.feedbackLevel) {
      if (mask) {
        struct PC {
          uint32_t width, height;
        } pc{uint32_t(width), uint32_t(height)};
        rec.dispatch("svgf_feedback_sampled", {levels_[cur], *mask, acc.current()}, pc, width, height);
      } else {
        rec.copy(levels_[cur].buffer, acc.current().buffer, 3 * planeBytes);
      }
    }
  }
  if (n == 0) rec.copy(source.buffer, levels_[cur].buffer, 3 * planeBytes);
  return levels_[cur];
}

}  // namespace rtd::svgf
#endif
