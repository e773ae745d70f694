#include "passes/neighbourhood_clipping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/parallel.h"

namespace rtd {

void clipGaussianWeights(int radius, float sigma, float* out) {
  float sum = 0.0f;
  for (int k = -radius; k <= radius; ++k) sum += out[k + radius] = std::exp(-float(k * k) / (2.0f * sigma * sigma));
  for (int k = 0; k <= 2 * radius; ++k) out[k] /= sum;
}

void clipBox(const Plane3& cur, const PixelVector<uint8_t>* clip, const ClipBoxOptions& opt, Plane3& low, Plane3& high,
             Plane3& blur) {
  const int w = cur[0].width, h = cur[0].height;
  const int R = opt.gaussianRadius, W = opt.windowRadius;
  std::vector<float> g(size_t(2 * R + 1));
  clipGaussianWeights(R, opt.sigma, g.data());
  for (Plane3* p : {&low, &high, &blur})
    if ((*p)[0].width != w || (*p)[0].height != h) resize(*p, w, h);
  constexpr float inf = std::numeric_limits<float>::infinity();
  for (int c = 0; c < 3; ++c) {
    const Plane& in = cur[c];
    // Separable Gaussian: rows into `low` (as scratch), then columns into `blur`.
    Plane& rows = low[c];
    parallelRows(h, [&](int y) {
      const float* s = in.row(y);
      float* o = rows.row(y);
      for (int x = 0; x < w; ++x) {
        float v = 0.0f;
        for (int k = -R; k <= R; ++k) v += g[k + R] * s[std::clamp(x + k, 0, w - 1)];
        o[x] = v;
      }
    });
    parallelRows(h, [&](int y) {
      float* o = blur[c].row(y);
      for (int x = 0; x < w; ++x) {
        float v = 0.0f;
        for (int k = -R; k <= R; ++k) v += g[k + R] * rows(x, std::clamp(y + k, 0, h - 1));
        o[x] = v;
      }
    });
    // Separable min / max over the window of the blurred image: along rows into low / high,
    // then along columns through `blur` (free again), swapped into place.
    parallelRows(h, [&](int y) {
      const float* s = blur[c].row(y);
      float *lo = low[c].row(y), *hi = high[c].row(y);
      for (int x = 0; x < w; ++x) {
        float a = inf, b = -inf;
        for (int k = std::max(0, x - W); k <= std::min(w - 1, x + W); ++k) {
          a = std::min(a, s[k]);
          b = std::max(b, s[k]);
        }
        lo[x] = a;
        hi[x] = b;
      }
    });
    parallelRows(h, [&](int y) {
      float* o = blur[c].row(y);
      for (int x = 0; x < w; ++x) {
        float a = inf;
        for (int k = std::max(0, y - W); k <= std::min(h - 1, y + W); ++k) a = std::min(a, low[c](x, k));
        o[x] = a;
      }
    });
    std::swap(low[c], blur[c]);
    parallelRows(h, [&](int y) {
      float* o = blur[c].row(y);
      for (int x = 0; x < w; ++x) {
        float b = -inf;
        for (int k = std::max(0, y - W); k <= std::min(h - 1, y + W); ++k) b = std::max(b, high[c](x, k));
        o[x] = b;
      }
    });
    std::swap(high[c], blur[c]);
  }
  if (!clip) return;
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x)
      if (!(*clip)[size_t(y) * w + x])
        for (int c = 0; c < 3; ++c) {
          low[c](x, y) = -inf;
          high[c](x, y) = inf;
        }
  });
}

}  // namespace rtd
