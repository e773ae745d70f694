#include "methods/svgf/svgf_passes.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <type_traits>
#include <vector>

#include "core/ivdep.h"
#include "core/parallel.h"
#include "methods/svgf/svgf_filter.h"

namespace rtd::svgf {

namespace {
bool spatialEstimate(const VarianceParams& p) {
  return p.shortHistory == SvgfShortHistory::spatialEstimate && p.shortHistoryFrames > 0;
}
}  // namespace

size_t varianceRows(const VarianceInputs& in, const VarianceParams& p, AtrousImage& out, PaddedPlane scratch[2],
                    int rowBegin, int rowEnd) {
  const int w = out.lum.width;
  const Plane3& acc = *in.accumulated;
  const bool spatial = spatialEstimate(p);
  size_t count = 0;
  // Colour, its luminance and the temporal variance everywhere; the window inputs (current
  // luminance and its square, or the accumulated moments) for the spatial estimate.
  // One instantiation per luminance, each loop free of branches, so that they vectorize.
  auto rows = [&](auto luminanceConstant) {
    constexpr MomentLuminance L = decltype(luminanceConstant)::value;
    const float shortFrames = float(p.shortHistoryFrames);
    for (int y = rowBegin; y < rowEnd; ++y) {
      const float* len = in.historyLength->row(y);
      const float *m1 = in.moment1->row(y), *m2 = in.moment2->row(y);
      const float *r = acc[0].row(y), *gg = acc[1].row(y), *b = acc[2].row(y);
      for (int c = 0; c < 3; ++c) std::copy(acc[c].row(y), acc[c].row(y) + w, out.color[c].row(y));
      float *lum = out.lum.row(y), *var = out.var.row(y);
      RTD_IVDEP  // eight planes: vectorized only without GCC's overlap checks
      for (int x = 0; x < w; ++x) {
        lum[x] = flushTiny(momentLuminance(L, r[x], gg[x], b[x]));
        var[x] = flushTiny(std::max(0.0f, m2[x] - squareOrZero(m1[x])));
        count += len[x] < shortFrames;
      }
      if (!spatial) continue;
      float *sa = scratch[0].row(y), *sb = scratch[1].row(y);
      if (p.fromMoments) {
        std::copy(m1, m1 + w, sa);
        std::copy(m2, m2 + w, sb);
        continue;
      }
      const float *cr = (*in.current)[0].row(y), *cg = (*in.current)[1].row(y), *cb = (*in.current)[2].row(y);
      for (int x = 0; x < w; ++x) {
        sa[x] = flushTiny(momentLuminance(L, cr[x], cg[x], cb[x]));
        sb[x] = squareOrZero(sa[x]);
      }
    }
  };
  switch (p.luminance) {
    case MomentLuminance::Rec601: rows(std::integral_constant<MomentLuminance, MomentLuminance::Rec601>{}); break;
    case MomentLuminance::CieLightness:
      rows(std::integral_constant<MomentLuminance, MomentLuminance::CieLightness>{});
      break;
    default: rows(std::integral_constant<MomentLuminance, MomentLuminance::Rec709>{});
  }
  return count;
}

size_t spatialVarianceEstimate(const AtrousGuide& g, const VarianceInputs& in, const VarianceParams& p,
                               AtrousImage& out, PaddedPlane scratch[2], size_t shortCount) {
  if (!spatialEstimate(p) || shortCount == 0) return 0;
  // Short history: depth/normal-weighted window estimate (Schied Sec. 4.2; Voorhuis Sec. 6
  // averages the accumulated moments instead of the current luminance).
  spatialVariance(g, scratch[0], scratch[1], *in.historyLength, float(p.shortHistoryFrames), p.radius, p.sigmaDepth,
                  p.depthEpsilon, p.depthEpsilonRelative, p.normalExponent, out.var, in.objectId);
  return shortCount;
}

size_t estimateVariance(const AtrousGuide& g, const VarianceInputs& in, const VarianceParams& p, AtrousImage& out,
                        PaddedPlane scratch[2]) {
  std::atomic<size_t> shortCount{0};
  tbb::parallel_for(tbb::blocked_range<int>(0, g.depth.height, 4), [&](const tbb::blocked_range<int>& r) {
    shortCount += varianceRows(in, p, out, scratch, r.begin(), r.end());
  });
  return spatialVarianceEstimate(g, in, p, out, scratch, shortCount.load());
}

void luminanceSigmaScale(const Plane& len, const SvgfSettings& s, PaddedPlane& out) {
  luminanceSigmaScale(len, filterParams(s, false), out);
}

float sampleCoverage(const Plane& mask, const Plane* hidden) {
  std::atomic<uint64_t> sampled{0}, visible{0};
  parallelRows(mask.height, [&](int y) {
    uint64_t s = 0, v = 0;
    const float* m = mask.row(y);
    const float* h = hidden ? hidden->row(y) : nullptr;
    for (int x = 0; x < mask.width; ++x) {
      if (h && h[x] > 0.5f) continue;
      ++v;
      s += m[x] != 0.0f;
    }
    sampled += s;
    visible += v;
  });
  if (sampled == visible) return 1.0f;
  // Below 1 however close: the share of one hole in more than 2^25 pixels rounds to 1.0f.
  return std::min(float(double(sampled) / double(visible)), std::nextafter(1.0f, 0.0f));
}

namespace {
inline float median3(float a, float b, float c) {
  const float lo = std::min(a, b), hi = std::max(a, b), m = std::min(hi, c);
  return std::max(lo, m);
}
}  // namespace

void median3x3(const Plane3& in, const Plane* roughness, Plane3& out) {
  const int w = in[0].width, h = in[0].height;
  // Exact 3x3 median without sorting nine values: sort each column of three, then the median
  // is the median of (the largest column minimum, the median of the column medians, the
  // smallest column maximum). The sorted columns of a row are shared by three pixels, and
  // both loops are branch-free min/max, so they vectorize. Edges clamp.
  parallelRows(h, [&](int y) {
    thread_local std::vector<float> lo, mid, hi;
    lo.resize(size_t(w) + 2);
    mid.resize(size_t(w) + 2);
    hi.resize(size_t(w) + 2);
    const float* rough = roughness ? roughness->row(y) : nullptr;
    for (int c = 0; c < 3; ++c) {
      const float* up = in[c].row(std::max(y - 1, 0));
      const float* cur = in[c].row(y);
      const float* down = in[c].row(std::min(y + 1, h - 1));
      float *l = lo.data() + 1, *m = mid.data() + 1, *u = hi.data() + 1;  // index -1 and w: the clamped edges
      // The loads into locals first: of std::min and std::max of array elements (references
      // to one or the other) GCC made conditional loads, and left the loops scalar.
      RTD_IVDEP
      for (int x = 0; x < w; ++x) {
        const float p = up[x], q = cur[x], r = down[x];
        const float a = std::min(p, q), b = std::max(p, q);
        l[x] = std::min(a, r);
        u[x] = std::max(b, r);
        m[x] = std::max(a, std::min(b, r));
      }
      l[-1] = l[0], m[-1] = m[0], u[-1] = u[0];
      l[w] = l[w - 1], m[w] = m[w - 1], u[w] = u[w - 1];
      float* o = out[c].row(y);
      auto median = [&](int x) {
        const float l0 = l[x - 1], l1 = l[x], l2 = l[x + 1], u0 = u[x - 1], u1 = u[x], u2 = u[x + 1];
        const float low = std::max(std::max(l0, l1), l2);
        const float high = std::min(std::min(u0, u1), u2);
        return median3(median3(m[x - 1], m[x], m[x + 1]), low, high);
      };
      // Voorhuis: diffuse pixels only (roughness >= 0.9), where the frame has roughness.
      if (rough) {
        RTD_IVDEP
        for (int x = 0; x < w; ++x) {
          const float med = median(x), keep = cur[x];
          o[x] = rough[x] < 0.9f ? keep : med;
        }
      } else {
        RTD_IVDEP
        for (int x = 0; x < w; ++x) o[x] = median(x);
      }
    }
  });
}

void levelSteps(SvgfLevelOrder order, int n, int* steps) {
  for (int i = 0; i < n; ++i) {
    switch (order) {
      case SvgfLevelOrder::fineToCoarse: steps[i] = 1 << i; break;
      case SvgfLevelOrder::coarseToFine: steps[i] = 1 << (n - 1 - i); break;
      case SvgfLevelOrder::firstThenCoarseToFine: steps[i] = i == 0 ? 1 : 1 << (n - i); break;
    }
  }
}

}  // namespace rtd::svgf
