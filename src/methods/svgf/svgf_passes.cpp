#include "methods/svgf/svgf_passes.h"

#include <atomic>

#include "core/parallel.h"

namespace rtd::svgf {

size_t estimateVariance(const AtrousGuide& g, const VarianceInputs& in, const VarianceParams& p, AtrousImage& out) {
  const int w = g.depth.width, h = g.depth.height;
  const Plane3& acc = *in.accumulated;
  std::atomic<size_t> spatialCount{0};
  const bool spatial = p.shortHistory == SvgfShortHistory::spatialEstimate && p.shortHistoryFrames > 0;
  const int R = std::min(p.radius, g.depth.pad);
  parallelRows(h, [&](int y) {
    size_t count = 0;
    const float* len = in.historyLength->row(y);
    const float *m1 = in.moment1->row(y), *m2 = in.moment2->row(y);
    for (int c = 0; c < 3; ++c) std::copy(acc[c].row(y), acc[c].row(y) + w, out.color[c].row(y));
    float* lum = out.lum.row(y);
    float* var = out.var.row(y);
    for (int x = 0; x < w; ++x) {
      lum[x] = momentLuminance(p.luminance, acc[0].row(y)[x], acc[1].row(y)[x], acc[2].row(y)[x]);
      if (!spatial || len[x] >= float(p.shortHistoryFrames)) {
        var[x] = std::max(0.0f, m2[x] - m1[x] * m1[x]);
        continue;
      }
      // Short history: depth/normal-weighted window estimate (Schied Sec. 4.2; Voorhuis Sec. 6
      // averages the accumulated moments instead of the current luminance). The border has
      // normal 0, so its taps weigh 0 and the clamped reads below are never used.
      ++count;
      const float zc = g.depth.at(x, y), gx = g.gradX.at(x, y), gy = g.gradY.at(x, y);
      const float nx = g.normal[0].at(x, y), ny = g.normal[1].at(x, y), nz = g.normal[2].at(x, y);
      double sw = 0, s1 = 0, s2 = 0;
      for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx) {
          const int qx = x + dx, qy = y + dy;
          float wt = 1.0f;
          if (dx || dy) {
            const float cosine = nx * g.normal[0].at(qx, qy) + ny * g.normal[1].at(qx, qy) + nz * g.normal[2].at(qx, qy);
            wt = normalWeight(cosine, p.normalExponent) *
                 depthWeight(zc, g.depth.at(qx, qy), gx * dx + gy * dy, p.sigmaDepth, p.depthEpsilon);
            if (!(wt > 0.0f)) continue;
          }
          const int cx = std::clamp(qx, 0, w - 1), cy = std::clamp(qy, 0, h - 1);
          float a, b;
          if (p.fromMoments) {
            a = (*in.moment1)(cx, cy);
            b = (*in.moment2)(cx, cy);
          } else {
            const Plane3& cur = *in.current;
            a = momentLuminance(p.luminance, cur[0](cx, cy), cur[1](cx, cy), cur[2](cx, cy));
            b = a * a;
          }
          sw += wt;
          s1 += wt * a;
          s2 += wt * b;
        }
      s1 /= sw;
      s2 /= sw;
      var[x] = float(std::max(0.0, s2 - s1 * s1));
    }
    spatialCount += count;
  });
  return spatialCount.load();
}

void luminanceSigmaScale(const Plane& len, const SvgfSettings& s, PaddedPlane& out) {
  const int w = len.width;
  const bool off = s.shortHistory == SvgfShortHistory::disableLuminanceWeight;
  parallelRows(len.height, [&](int y) {
    const float* n = len.row(y);
    float* o = out.row(y);
    for (int x = 0; x < w; ++x) {
      if (off && n[x] < float(s.shortHistoryFrames)) {
        o[x] = 0.0f;
        continue;
      }
      // h = successful reprojections = history length - 1.
      o[x] = s.shortHistoryBandwidth ? shortHistoryBandwidthScale(int(n[x]) - 1) : 1.0f;
    }
  });
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
