#include "methods/svgf/svgf_passes.h"

#include <atomic>

#include "core/parallel.h"
#include "methods/svgf/svgf_filter.h"

namespace rtd::svgf {

size_t estimateVariance(const AtrousGuide& g, const VarianceInputs& in, const VarianceParams& p, AtrousImage& out,
                        PaddedPlane scratch[2]) {
  const int w = g.depth.width, h = g.depth.height;
  const Plane3& acc = *in.accumulated;
  std::atomic<size_t> spatialCount{0};
  const bool spatial = p.shortHistory == SvgfShortHistory::spatialEstimate && p.shortHistoryFrames > 0;
  // Colour, its luminance and the temporal variance everywhere; the window inputs (current
  // luminance and its square, or the accumulated moments) for the spatial estimate.
  parallelRows(h, [&](int y) {
    size_t count = 0;
    const float* len = in.historyLength->row(y);
    const float *m1 = in.moment1->row(y), *m2 = in.moment2->row(y);
    const float *r = acc[0].row(y), *gg = acc[1].row(y), *b = acc[2].row(y);
    for (int c = 0; c < 3; ++c) std::copy(acc[c].row(y), acc[c].row(y) + w, out.color[c].row(y));
    float *lum = out.lum.row(y), *var = out.var.row(y);
    float *sa = scratch[0].row(y), *sb = scratch[1].row(y);
    const Plane3* cur = in.current;
    for (int x = 0; x < w; ++x) {
      lum[x] = flushTiny(momentLuminance(p.luminance, r[x], gg[x], b[x]));
      var[x] = flushTiny(std::max(0.0f, m2[x] - squareOrZero(m1[x])));
      count += len[x] < float(p.shortHistoryFrames);
      if (!spatial) continue;
      if (p.fromMoments) {
        sa[x] = m1[x];
        sb[x] = m2[x];
      } else {
        sa[x] = flushTiny(momentLuminance(p.luminance, (*cur)[0].row(y)[x], (*cur)[1].row(y)[x], (*cur)[2].row(y)[x]));
        sb[x] = squareOrZero(sa[x]);
      }
    }
    spatialCount += count;
  });
  const size_t count = spatialCount.load();
  if (!spatial || count == 0) return 0;
  // Short history: depth/normal-weighted window estimate (Schied Sec. 4.2; Voorhuis Sec. 6
  // averages the accumulated moments instead of the current luminance).
  spatialVariance(g, scratch[0], scratch[1], *in.historyLength, float(p.shortHistoryFrames), p.radius, p.sigmaDepth,
                  p.depthEpsilon, p.normalExponent, out.var, in.objectId);
  return count;
}

void luminanceSigmaScale(const Plane& len, const SvgfSettings& s, PaddedPlane& out) {
  luminanceSigmaScale(len, filterParams(s, false), out);
}

void median3x3(const Plane3& in, const Plane* roughness, Plane3& out) {
  const int w = in[0].width, h = in[0].height;
  parallelRows(h, [&](int y) {
    for (int c = 0; c < 3; ++c) {
      const Plane& p = in[c];
      float* o = out[c].row(y);
      for (int x = 0; x < w; ++x) {
        if (roughness && (*roughness)(x, y) < 0.9f) {
          o[x] = p(x, y);
          continue;
        }
        float v[9];
        int k = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) v[k++] = p(std::clamp(x + dx, 0, w - 1), std::clamp(y + dy, 0, h - 1));
        std::nth_element(v, v + 4, v + 9);
        o[x] = v[4];
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
