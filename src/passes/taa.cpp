#include "passes/taa.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace rtd {

namespace {
struct YCoCg {
  float y, co, cg;
};
inline YCoCg toYCoCg(float r, float g, float b) {
  return {0.25f * r + 0.5f * g + 0.25f * b, 0.5f * r - 0.5f * b, -0.25f * r + 0.5f * g - 0.25f * b};
}
inline void fromYCoCg(const YCoCg& c, float& r, float& g, float& b) {
  r = c.y + c.co - c.cg;
  g = c.y + c.cg;
  b = c.y - c.co - c.cg;
}
}  // namespace

void Taa::resize(int w, int h) {
  for (Plane3* p : {&history_, &ycocg_, &rowMin_, &rowMax_, &lo_, &hi_}) rtd::resize(*p, w, h);
  valid_ = false;
}

namespace {
// out[x] = op(in[x-1], in[x], in[x+1]) with the border pixel repeated.
template <class Op> void horizontal3(const float* in, float* out, int w, Op op) {
  if (w == 1) { out[0] = in[0]; return; }
  out[0] = op(in[0], in[1]);
  for (int x = 1; x < w - 1; ++x) out[x] = op(op(in[x - 1], in[x]), in[x + 1]);
  out[w - 1] = op(in[w - 2], in[w - 1]);
}
inline float fmin(float a, float b) { return a < b ? a : b; }
inline float fmax(float a, float b) { return a > b ? a : b; }
}  // namespace

void Taa::run(const Reprojection& rp, const Plane3& color, float alpha, Plane3& out) {
  const int w = color[0].width, h = color[0].height;
  if (history_[0].width != w || history_[0].height != h || lo_[0].width != w) resize(w, h);
  for (auto& p : out)
    if (p.width != w || p.height != h) p.resize(w, h);
  if (!valid_) {
    for (int c = 0; c < 3; ++c) { out[c].data = color[c].data; history_[c].data = color[c].data; }
    valid_ = true;
    return;
  }
  // The min/max box of the 3x3 neighbourhood in YCoCg, separably: rows, then columns. Every
  // loop here runs over whole rows and vectorizes.
  parallelRows(h, [&](int y) {
    const float *r = color[0].row(y), *g = color[1].row(y), *b = color[2].row(y);
    float *Y = ycocg_[0].row(y), *Co = ycocg_[1].row(y), *Cg = ycocg_[2].row(y);
    for (int x = 0; x < w; ++x) {
      Y[x] = 0.25f * r[x] + 0.5f * g[x] + 0.25f * b[x];
      Co[x] = 0.5f * r[x] - 0.5f * b[x];
      Cg[x] = -0.25f * r[x] + 0.5f * g[x] - 0.25f * b[x];
    }
    for (int c = 0; c < 3; ++c) {
      horizontal3(ycocg_[c].row(y), rowMin_[c].row(y), w, fmin);
      horizontal3(ycocg_[c].row(y), rowMax_[c].row(y), w, fmax);
    }
  });
  parallelRows(h, [&](int y) {
    const int ya = std::max(y - 1, 0), yb = std::min(y + 1, h - 1);
    for (int c = 0; c < 3; ++c) {
      const float *a0 = rowMin_[c].row(ya), *a1 = rowMin_[c].row(y), *a2 = rowMin_[c].row(yb);
      const float *b0 = rowMax_[c].row(ya), *b1 = rowMax_[c].row(y), *b2 = rowMax_[c].row(yb);
      float *lo = lo_[c].row(y), *hi = hi_[c].row(y);
      for (int x = 0; x < w; ++x) {
        lo[x] = fmin(fmin(a0[x], a1[x]), a2[x]);
        hi[x] = fmax(fmax(b0[x], b1[x]), b2[x]);
      }
    }
  });
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const YCoCg cur{ycocg_[0].data[i], ycocg_[1].data[i], ycocg_[2].data[i]};
      const float px = rp.prevX.data[i] - 0.5f, py = rp.prevY.data[i] - 0.5f;
      float r = color[0].data[i], g = color[1].data[i], b = color[2].data[i];
      if (px > -1.0f && py > -1.0f && px < float(w) && py < float(h)) {
        // Bilinear history fetch with clamp-to-edge.
        const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
        const float ax = px - x0, ay = py - y0;
        const float wt[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
        float hist[3] = {0, 0, 0};
        if (x0 >= 0 && y0 >= 0 && x0 < w - 1 && y0 < h - 1) {
          // Interior: the four taps without clamping.
          const size_t j = size_t(y0) * w + x0;
          for (int c = 0; c < 3; ++c) {
            const float* hp = history_[c].ptr() + j;
            hist[c] = wt[0] * hp[0] + wt[1] * hp[1] + wt[2] * hp[w] + wt[3] * hp[w + 1];
          }
        } else {
          for (int t = 0; t < 4; ++t) {
            const int tx = std::clamp(x0 + (t & 1), 0, w - 1), ty = std::clamp(y0 + (t >> 1), 0, h - 1);
            for (int c = 0; c < 3; ++c) hist[c] += wt[t] * history_[c](tx, ty);
          }
        }
        YCoCg hy = toYCoCg(hist[0], hist[1], hist[2]);
        hy = {std::clamp(hy.y, lo_[0].data[i], hi_[0].data[i]), std::clamp(hy.co, lo_[1].data[i], hi_[1].data[i]),
              std::clamp(hy.cg, lo_[2].data[i], hi_[2].data[i])};
        const YCoCg blended{alpha * cur.y + (1 - alpha) * hy.y, alpha * cur.co + (1 - alpha) * hy.co,
                            alpha * cur.cg + (1 - alpha) * hy.cg};
        fromYCoCg(blended, r, g, b);
      }
      out[0].data[i] = std::max(r, 0.0f);
      out[1].data[i] = std::max(g, 0.0f);
      out[2].data[i] = std::max(b, 0.0f);
    }
  });
  for (int c = 0; c < 3; ++c) history_[c].data = out[c].data;
}

}  // namespace rtd
