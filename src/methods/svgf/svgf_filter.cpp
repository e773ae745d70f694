#include "methods/svgf/svgf_filter.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "core/parallel.h"
#include "passes/demodulation.h"

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

// out = colour * albedo' (AtrousLevel::remodulatedOut's product, where no level writes it).
void remodulateInto(const AtrousImage& level, const std::vector<Plane>* albedo, Plane3& out) {
  parallelRows(out[0].height, [&](int y) {
    for (int c = 0; c < 3; ++c)
      remodulateSpan(level.color[c].row(y), albedo ? (*albedo)[c].row(y) : nullptr, out[c].row(y), out[0].width);
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

size_t Filter::varianceRows(const TemporalAccumulator& acc, const Plane3& current, const FilterParams& p, int rowBegin,
                            int rowEnd) {
  const VarianceInputs in{&acc.historyLength(), &acc.moment1(), &acc.moment2(), &current, &acc.color(), nullptr};
  return svgf::varianceRows(in, p.variance, levels_[0], scratch_, rowBegin, rowEnd);
}

bool usesSigmaScale(const FilterParams& p) {
  return p.variance.shortHistory == SvgfShortHistory::disableLuminanceWeight || p.shortHistoryBandwidth;
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
  for (auto& v : scratch_) v.resize(w, h, pad);
  // What only some settings use is allocated by run() when they first do.
  sigmaScale_ = {};
  for (auto& v : valid_) v = {};
  prefilteredVariance_ = {};
}


const AtrousImage& Filter::run(const AtrousGuide& guide, TemporalAccumulator& acc, const Plane3& current,
                               const Plane* mask, const FilterParams& p, FrameStats& stats, const std::string& suffix,
                               const FilterExtras& extras) {
  const Plane3& input = extras.input ? *extras.input : acc.color();
  const int w = levels_[0].var.width, h = levels_[0].var.height;  // what run() allocates on first use
  {
    PassTimer t(stats, "variance" + suffix);
    VarianceInputs in{&acc.historyLength(), &acc.moment1(), &acc.moment2(), &current, &input,
                      extras.objectId ? extras.objectId : p.surfaceKey};
    assert(!(extras.varianceRowsShortCount && extras.input));  // the rows read accumulator.color()
    if (extras.varianceRowsShortCount)
      spatialVarianceEstimate(guide, in, p.variance, levels_[0], scratch_, *extras.varianceRowsShortCount);
    else
      estimateVariance(guide, in, p.variance, levels_[0], scratch_);
    // k(p) is 1 everywhere unless short histories change it: then no plane (every level reads
    // one value less per pixel, and this pass writes none).
    if (usesSigmaScale(p)) {
      allocateOnce(sigmaScale_, w, h, pad_);
      luminanceSigmaScale(acc.historyLength(), p, sigmaScale_);
    }
    if (mask) {
      for (auto& v : valid_) allocateOnce(v, w, h, pad_);
      markValid(acc.historyLength(), valid_[0]);
    }
    if (p.variancePrefilter == SvgfVariancePrefilter::once) {
      allocateOnce(prefilteredVariance_, w, h, pad_);
      gaussian3x3(levels_[0].var, prefilteredVariance_);
      std::swap(levels_[0].var, prefilteredVariance_);
    }
  }
  const int n = p.iterations;
  int steps[8];
  levelSteps(p.levelOrder, n, steps);
  // The last level writes the remodulated result itself where its colour is not needed as it
  // is (fed back) and its weights are the plain ones (AtrousLevel::remodulatedOut).
  const bool fuse = extras.remodulatedOut && n > 0 && p.feedbackLevel != n && !p.spatialFalloff && !p.surfaceKey &&
                    !extras.indirectDistance;
  int cur = 0;
  for (int i = 0; i < n; ++i) {
    const bool last = fuse && i + 1 == n;
    PassTimer t(stats, "atrous" + std::to_string(i + 1) + (last ? "+remodulate" : "") + suffix);
    AtrousImage& src = levels_[cur];
    AtrousImage& dst = levels_[cur ^ 1];
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
    lv.sigmaScale = usesSigmaScale(p) ? &sigmaScale_ : nullptr;
    // The last level's variance is not used any more.
    lv.propagateVariance = p.propagateVariance && i + 1 < n;
    lv.luminance = p.variance.luminance;
    lv.indirectDistance = extras.indirectDistance;
    lv.indirectDistanceScale = extras.indirectDistanceScale;
    lv.centreScale = extras.centreScale;
    lv.spatialFalloff = p.spatialFalloff;
    lv.surfaceKey = p.surfaceKey;
    if (last) {
      lv.remodulatedOut = extras.remodulatedOut;
      lv.remodulateAlbedo = extras.remodulateAlbedo;
    }
    if (mask) {
      lv.validIn = &valid_[cur];
      lv.validOut = &valid_[cur ^ 1];
    }
    atrousLevel(guide, lv, src, dst);
    if (!lv.propagateVariance) std::swap(src.var, dst.var);  // keep the unfiltered variance
    cur ^= 1;
    if (i + 1 == p.feedbackLevel) {
      // The first level's output becomes next frame's colour history (Schied Sec. 4.3).
      Plane3& history = acc.color();
      if (mask) feedbackSampled(levels_[cur], *mask, history);
      else for (int c = 0; c < 3; ++c) levels_[cur].color[c].copyTo(history[c]);
    }
  }
  // Without levels the result is the accumulation itself.
  if (n == 0)
    for (int c = 0; c < 3; ++c) levels_[cur].color[c].copyFrom(input[c]);
  if (extras.remodulatedOut && !fuse) {
    PassTimer t(stats, "remodulate" + suffix);
    remodulateInto(levels_[cur], extras.remodulateAlbedo, *extras.remodulatedOut);
  }
  return levels_[cur];
}

}  // namespace rtd::svgf
