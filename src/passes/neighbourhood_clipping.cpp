#include "passes/neighbourhood_clipping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/parallel.h"
#include "rtd/error.h"

namespace rtd {

void clipGaussianWeights(int radius, float sigma, float* out) {
  float sum = 0.0f;
  for (int k = -radius; k <= radius; ++k) sum += out[k + radius] = std::exp(-float(k * k) / (2.0f * sigma * sigma));
  for (int k = 0; k <= 2 * radius; ++k) out[k] /= sum;
}

namespace {

// clipBox with `surface`: the same Gaussian and window, but each restricted to the pixels of
// one surface key, so they cannot be separated; evaluated at clipped pixels only (the window
// of a clipped pixel reads pixels of its own key, hence clipped ones).
void clipBoxOnSurfaces(const Plane3& cur, const PixelVector<uint8_t>& clip, const PixelVector<uint32_t>& surface,
                       const std::vector<float>& g, int R, int W, Plane3& low, Plane3& high, Plane3& blur) {
  const int w = cur[0].width, h = cur[0].height;
  constexpr float inf = std::numeric_limits<float>::infinity();
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (!clip[i]) continue;
      const uint32_t key = surface[i];
      float v[3] = {0, 0, 0}, sum = 0.0f;
      for (int l = -R; l <= R; ++l) {
        const int qy = std::clamp(y + l, 0, h - 1);
        for (int k = -R; k <= R; ++k) {
          const size_t j = size_t(qy) * w + std::clamp(x + k, 0, w - 1);
          if (surface[j] != key) continue;
          const float gw = g[size_t(l + R)] * g[size_t(k + R)];
          sum += gw;
          for (int c = 0; c < 3; ++c) v[c] += gw * cur[c].data[j];
        }
      }
      for (int c = 0; c < 3; ++c) blur[c].data[i] = v[c] / sum;  // sum > 0: the centre tap counts
    }
  });
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      float lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
      if (clip[i]) {
        const uint32_t key = surface[i];
        for (int qy = std::max(0, y - W); qy <= std::min(h - 1, y + W); ++qy)
          for (int qx = std::max(0, x - W); qx <= std::min(w - 1, x + W); ++qx) {
            const size_t j = size_t(qy) * w + qx;
            if (surface[j] != key) continue;
            for (int c = 0; c < 3; ++c) {
              lo[c] = std::min(lo[c], blur[c].data[j]);
              hi[c] = std::max(hi[c], blur[c].data[j]);
            }
          }
      } else {
        for (int c = 0; c < 3; ++c) lo[c] = -inf, hi[c] = inf;
      }
      for (int c = 0; c < 3; ++c) {
        low[c].data[i] = lo[c];
        high[c].data[i] = hi[c];
      }
    }
  });
}

}  // namespace

void clipBox(const Plane3& cur, const PixelVector<uint8_t>* clip, const ClipBoxOptions& opt, Plane3& low, Plane3& high,
             Plane3& blur, const PixelVector<uint32_t>* surface) {
  const int w = cur[0].width, h = cur[0].height;
  const int R = opt.gaussianRadius, W = opt.windowRadius;
  std::vector<float> g(size_t(2 * R + 1));
  clipGaussianWeights(R, opt.sigma, g.data());
  for (Plane3* p : {&low, &high, &blur})
    if ((*p)[0].width != w || (*p)[0].height != h) resize(*p, w, h);
  if (surface) {
    if (!clip) throw Error("clipBox: a surface key needs the clip mask");
    clipBoxOnSurfaces(cur, *clip, *surface, g, R, W, low, high, blur);
    return;
  }
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
