#include "methods/svgf/svgf_filter.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace rtd::svgf {

namespace {

MomentLuminance toMomentLuminance(SvgfLuminance l) {
  switch (l) {
    case SvgfLuminance::rec601: return MomentLuminance::Rec601;
    case SvgfLuminance::cieLightness: return MomentLuminance::CieLightness;
    default: return MomentLuminance::Rec709;
  }
}

// Level-0 validity: pixels with any accumulated data.
void markValid(const Plane& length, PaddedPlane& valid) {
  const int w = length.width;
  parallelRows(length.height, [&](int y) {
    const float* n = length.row(y);
    float* v = valid.row(y);
    for (int x = 0; x < w; ++x) v[x] = n[x] > 0.0f ? 1.0f : 0.0f;
  });
}

// Dundr Sec. 5: feeding the filtered level back everywhere would blur untouched samples
// again every frame; only pixels sampled this frame take the filtered value.
void feedbackSampled(const AtrousImage& level, const Plane& mask, Plane3& history) {
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

}  // namespace

int FilterParams::requiredPad() const {
  const int r = kernel == SvgfKernel::b3spline5x5 ? 2 : 1;
  const int maxStep = iterations > 0 ? 1 << (iterations - 1) : 1;
  return std::max({r * maxStep, variance.radius, 8});
}

FilterParams filterParams(const SvgfSettings& s, bool indirect) {
  FilterParams p;
  VarianceParams& v = p.variance;
  v.shortHistoryFrames = s.shortHistoryFrames;
  v.shortHistory = s.shortHistory;
  v.radius = s.spatialVarianceRadius;
  v.fromMoments = s.spatialVarianceFromMoments;
  v.sigmaDepth = s.sigmaDepth;
  setDepthEpsilon(v, s.depthEpsilon, s.depthEpsilonRelative);
  v.normalExponent = std::max(1, int(std::lround(s.sigmaNormal)));
  v.luminance = toMomentLuminance(s.luminance);
  p.variancePrefilter = s.variancePrefilter;
  p.shortHistoryBandwidth = s.shortHistoryBandwidth;
  p.kernel = s.kernel;
  p.iterations = s.atrousIterations;
  p.levelOrder = s.levelOrder;
  p.feedbackLevel = s.feedbackLevel;
  p.sigmaLuminance = s.sigmaLuminance;
  p.luminanceEpsilon = s.luminanceEpsilon;
  p.luminanceScale = s.luminanceScale;
  p.propagateVariance = s.varianceFiltering && !(indirect && !s.indirectVarianceFiltering);
  return p;
}

void luminanceSigmaScale(const Plane& len, const FilterParams& p, PaddedPlane& out) {
  const int w = len.width;
  const bool off = p.variance.shortHistory == SvgfShortHistory::disableLuminanceWeight;
  const float shortFrames = float(p.variance.shortHistoryFrames);
  parallelRows(len.height, [&](int y) {
    const float* n = len.row(y);
    float* o = out.row(y);
    for (int x = 0; x < w; ++x) {
      if (off && n[x] < shortFrames) {
        o[x] = 0.0f;
        continue;
      }
      // h = successful reprojections = history length - 1.
      o[x] = p.shortHistoryBandwidth ? shortHistoryBandwidthScale(int(n[x]) - 1) : 1.0f;
    }
  });
}

void Filter::resize(int w, int h, int pad) {
  pad_ = pad;
  for (auto& im : levels_) im.resize(w, h, pad);
  sigmaScale_.resize(w, h, pad);
  for (auto& v : valid_) v.resize(w, h, pad);
  for (auto& v : scratch_) v.resize(w, h, pad);
}

void Filter::variance(const AtrousGuide& guide, TemporalAccumulator& acc, const Plane3& current, const Plane* mask,
                      const FilterParams& p, FrameStats& stats, const std::string& suffix, const FilterExtras& extras) {
  const Plane3& input = extras.input ? *extras.input : acc.color();
  PassTimer t(stats, "variance" + suffix);
  VarianceInputs in{&acc.historyLength(), &acc.moment1(), &acc.moment2(), &current, &input, extras.objectId};
  estimateVariance(guide, in, p.variance, levels_[0], scratch_);
  luminanceSigmaScale(acc.historyLength(), p, sigmaScale_);
  if (mask) markValid(acc.historyLength(), valid_[0]);
  if (p.variancePrefilter == SvgfVariancePrefilter::once) {
    gaussian3x3(levels_[0].var, levels_[2].var);
    std::swap(levels_[0].var, levels_[2].var);
  }
  cur_ = 0;
}

AtrousLevel Filter::level(int i, const FilterParams& p, const Plane* mask, const FilterExtras& extras) {
  int steps[8];
  levelSteps(p.levelOrder, p.iterations, steps);
  AtrousLevel lv;
  lv.kernel = p.kernel == SvgfKernel::b3spline5x5 ? AtrousKernel::B3Spline5x5 : AtrousKernel::Binomial3x3;
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
  // The last level's variance is not used any more.
  lv.propagateVariance = p.propagateVariance && i + 1 < p.iterations;
  lv.luminance = p.variance.luminance;
  lv.indirectDistance = extras.indirectDistance;
  lv.indirectDistanceScale = extras.indirectDistanceScale;
  lv.centreScale = extras.centreScale;
  lv.spatialFalloff = p.spatialFalloff;
  if (mask) {
    lv.validIn = &valid_[cur_];
    lv.validOut = &valid_[cur_ ^ 1];
  }
  return lv;
}

void Filter::advance(int i, const AtrousLevel& lv, TemporalAccumulator& acc, const Plane* mask, const FilterParams& p) {
  AtrousImage& src = levels_[cur_];
  AtrousImage& dst = levels_[cur_ ^ 1];
  if (!lv.propagateVariance) std::swap(src.var, dst.var);  // keep the unfiltered variance
  cur_ ^= 1;
  if (i + 1 == p.feedbackLevel) {
    // The first level's output becomes next frame's colour history (Schied Sec. 4.3).
    Plane3& history = acc.color();
    if (mask) feedbackSampled(levels_[cur_], *mask, history);
    else for (int c = 0; c < 3; ++c) levels_[cur_].color[c].copyTo(history[c]);
  }
}

const AtrousImage& Filter::finish(const FilterParams& p, const Plane3& input) {
  // Without levels the result is the accumulation itself.
  if (p.iterations == 0)
    for (int c = 0; c < 3; ++c) levels_[cur_].color[c].copyFrom(input[c]);
  return levels_[cur_];
}

const AtrousImage& Filter::run(const AtrousGuide& guide, TemporalAccumulator& acc, const Plane3& current,
                               const Plane* mask, const FilterParams& p, FrameStats& stats, const std::string& suffix,
                               const FilterExtras& extras) {
  variance(guide, acc, current, mask, p, stats, suffix, extras);
  for (int i = 0; i < p.iterations; ++i) {
    PassTimer t(stats, "atrous" + std::to_string(i + 1) + suffix);
    const AtrousLevel lv = level(i, p, mask, extras);
    atrousLevel(guide, lv, levels_[cur_], levels_[cur_ ^ 1]);
    advance(i, lv, acc, mask, p);
  }
  return finish(p, extras.input ? *extras.input : acc.color());
}

std::pair<const AtrousImage*, const AtrousImage*> Filter::runPair(Filter& a, Filter& b, const AtrousGuide& guide,
                                                                 const PairStream& sa, const PairStream& sb,
                                                                 FrameStats& stats) {
  a.variance(guide, *sa.accumulator, *sa.current, nullptr, *sa.params, stats, sa.suffix, {});
  b.variance(guide, *sb.accumulator, *sb.current, nullptr, *sb.params, stats, sb.suffix, {});
  const int na = sa.params->iterations, nb = sb.params->iterations;
  // ".direct" and ".indirect" make ".direct+indirect".
  const std::string both = sa.suffix + "+" + (sb.suffix.empty() ? sb.suffix : sb.suffix.substr(1));
  for (int i = 0; i < std::max(na, nb); ++i) {
    const std::string name = "atrous" + std::to_string(i + 1);
    const AtrousLevel la = i < na ? a.level(i, *sa.params, nullptr, {}) : AtrousLevel{};
    const AtrousLevel lb = i < nb ? b.level(i, *sb.params, nullptr, {}) : AtrousLevel{};
    if (i < na && i < nb && la.sharesGeometry(lb)) {
      PassTimer t(stats, name + both);
      atrousLevels(guide, la, a.levels_[a.cur_], a.levels_[a.cur_ ^ 1], lb, b.levels_[b.cur_], b.levels_[b.cur_ ^ 1]);
      a.advance(i, la, *sa.accumulator, nullptr, *sa.params);
      b.advance(i, lb, *sb.accumulator, nullptr, *sb.params);
      continue;
    }
    if (i < na) {
      PassTimer t(stats, name + sa.suffix);
      atrousLevel(guide, la, a.levels_[a.cur_], a.levels_[a.cur_ ^ 1]);
      a.advance(i, la, *sa.accumulator, nullptr, *sa.params);
    }
    if (i < nb) {
      PassTimer t(stats, name + sb.suffix);
      atrousLevel(guide, lb, b.levels_[b.cur_], b.levels_[b.cur_ ^ 1]);
      b.advance(i, lb, *sb.accumulator, nullptr, *sb.params);
    }
  }
  return {&a.finish(*sa.params, sa.accumulator->color()), &b.finish(*sb.params, sb.accumulator->color())};
}

}  // namespace rtd::svgf
