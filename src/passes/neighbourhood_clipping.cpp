#include "passes/neighbourhood_clipping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/ivdep.h"
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
// one surface key, so they cannot be separated; needed at clipped pixels only (the window of a
// clipped pixel reads pixels of its own key, hence clipped ones), so rows without one are
// skipped. In a row with one, the columns whose taps all lie inside the row are computed for
// every pixel in loops over x with the key test as a select (a tap of another key adds 0 to
// the sums, or leaves the bounds), which vectorize; the border columns pixel by pixel. Each
// pixel's sums take their taps in the same order either way: the same bits.
void clipBoxOnSurfaces(const Plane3& cur, const PixelVector<uint8_t>& clip, const PixelVector<uint32_t>& surface,
                       const std::vector<float>& g, int R, int W, Plane3& low, Plane3& high, Plane3& blur) {
  const int w = cur[0].width, h = cur[0].height;
  constexpr float inf = std::numeric_limits<float>::infinity();
  auto anyClipped = [&](int y) {
    const uint8_t* m = clip.data() + size_t(y) * w;
    return std::any_of(m, m + w, [](uint8_t v) { return v != 0; });
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
    std::vector<float> sum(static_cast<size_t>(w));  // the prefilter weights' sums of a row
    for (int y = rows.begin(); y != rows.end(); ++y) {
      if (!anyClipped(y)) continue;
      const size_t i0 = size_t(y) * w;
      const uint32_t* key = surface.data() + i0;
      float* b[3] = {blur[0].row(y), blur[1].row(y), blur[2].row(y)};
      // The prefilter at (x, y) over the taps of its key (renormalized; the centre counts).
      auto gaussianAt = [&](int x) {
        float v[3] = {0, 0, 0}, s = 0.0f;
        for (int l = -R; l <= R; ++l) {
          const int qy = std::clamp(y + l, 0, h - 1);
          for (int k = -R; k <= R; ++k) {
            const size_t j = size_t(qy) * w + std::clamp(x + k, 0, w - 1);
            if (surface[j] != key[x]) continue;
            const float gw = g[size_t(l + R)] * g[size_t(k + R)];
            s += gw;
            for (int c = 0; c < 3; ++c) v[c] += gw * cur[c].data[j];
          }
        }
        for (int c = 0; c < 3; ++c) b[c][x] = v[c] / s;
      };
      const int gx0 = std::min(R, w), gx1 = std::max(gx0, w - R);  // taps inside the row
      std::fill(sum.begin() + gx0, sum.begin() + gx1, 0.0f);
      for (int c = 0; c < 3; ++c) std::fill(b[c] + gx0, b[c] + gx1, 0.0f);
      for (int l = -R; l <= R; ++l) {
        const int qy = std::clamp(y + l, 0, h - 1);
        const uint32_t* qk = surface.data() + size_t(qy) * w;
        const float *q0 = cur[0].row(qy), *q1 = cur[1].row(qy), *q2 = cur[2].row(qy);
        for (int k = -R; k <= R; ++k) {
          const float gw = g[size_t(l + R)] * g[size_t(k + R)];
          float *s = sum.data(), *b0 = b[0], *b1 = b[1], *b2 = b[2];
          RTD_IVDEP
          for (int x = gx0; x < gx1; ++x) {
            const float m = qk[x + k] == key[x] ? gw : 0.0f;
            s[x] += m;
            b0[x] += m * q0[x + k];
            b1[x] += m * q1[x + k];
            b2[x] += m * q2[x + k];
          }
        }
      }
      for (int c = 0; c < 3; ++c)
        for (int x = gx0; x < gx1; ++x) b[c][x] /= sum[size_t(x)];
      for (int x = 0; x < w; ++x)
        if ((x < gx0 || x >= gx1) && clip[i0 + size_t(x)]) gaussianAt(x);
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      const size_t i0 = size_t(y) * w;
      float* lo[3] = {low[0].row(y), low[1].row(y), low[2].row(y)};
      float* hi[3] = {high[0].row(y), high[1].row(y), high[2].row(y)};
      if (anyClipped(y)) {
        const uint32_t* key = surface.data() + i0;
        for (int c = 0; c < 3; ++c) {
          std::fill(lo[c], lo[c] + w, inf);
          std::fill(hi[c], hi[c] + w, -inf);
        }
        const int qy0 = std::max(0, y - W), qy1 = std::min(h - 1, y + W);
        // Min / max over the window's pixels of the key at (x, y).
        auto boundsAt = [&](int x) {
          for (int qy = qy0; qy <= qy1; ++qy)
            for (int qx = std::max(0, x - W); qx <= std::min(w - 1, x + W); ++qx) {
              const size_t j = size_t(qy) * w + qx;
              if (surface[j] != key[x]) continue;
              for (int c = 0; c < 3; ++c) {
                lo[c][x] = std::min(lo[c][x], blur[c].data[j]);
                hi[c][x] = std::max(hi[c][x], blur[c].data[j]);
              }
            }
        };
        const int wx0 = std::min(W, w), wx1 = std::max(wx0, w - W);  // windows inside the row
        for (int qy = qy0; qy <= qy1; ++qy) {
          const uint32_t* qk = surface.data() + size_t(qy) * w;
          for (int c = 0; c < 3; ++c) {
            const float* q = blur[c].row(qy);
            float *l = lo[c], *u = hi[c];
            for (int k = -W; k <= W; ++k) {
              RTD_IVDEP
              for (int x = wx0; x < wx1; ++x) {
                // std::min and std::max written out as selects of values, which GCC
                // if-converts (of the references they return it did not).
                const bool same = qk[x + k] == key[x];
                const float v = q[x + k], a = l[x], z = u[x];
                l[x] = same && v < a ? v : a;
                u[x] = same && z < v ? v : z;
              }
            }
          }
        }
        for (int x = 0; x < w; ++x)
          if ((x < wx0 || x >= wx1) && clip[i0 + size_t(x)]) boundsAt(x);
      }
      for (int x = 0; x < w; ++x)
        if (!clip[i0 + size_t(x)])
          for (int c = 0; c < 3; ++c) lo[c][x] = -inf, hi[c][x] = inf;
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
