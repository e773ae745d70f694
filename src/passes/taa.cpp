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
  rtd::resize(history_, w, h);
  valid_ = false;
}

void Taa::run(const Reprojection& rp, const Plane3& color, float alpha, Plane3& out) {
  const int w = color[0].width, h = color[0].height;
  if (history_[0].width != w || history_[0].height != h) resize(w, h);
  for (auto& p : out)
    if (p.width != w || p.height != h) p.resize(w, h);
  if (!valid_) {
    for (int c = 0; c < 3; ++c) { out[c].data = color[c].data; history_[c].data = color[c].data; }
    valid_ = true;
    return;
  }
  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      YCoCg cur = toYCoCg(color[0].data[i], color[1].data[i], color[2].data[i]);
      YCoCg lo = cur, hi = cur;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
          const size_t j = size_t(yy) * w + xx;
          YCoCg n = toYCoCg(color[0].data[j], color[1].data[j], color[2].data[j]);
          lo = {std::min(lo.y, n.y), std::min(lo.co, n.co), std::min(lo.cg, n.cg)};
          hi = {std::max(hi.y, n.y), std::max(hi.co, n.co), std::max(hi.cg, n.cg)};
        }
      const float px = rp.prevX.data[i] - 0.5f, py = rp.prevY.data[i] - 0.5f;
      float r = color[0].data[i], g = color[1].data[i], b = color[2].data[i];
      if (px > -1.0f && py > -1.0f && px < float(w) && py < float(h)) {
        // Bilinear history fetch with clamp-to-edge.
        const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
        const float ax = px - x0, ay = py - y0;
        float hist[3] = {0, 0, 0};
        for (int t = 0; t < 4; ++t) {
          const int tx = std::clamp(x0 + (t & 1), 0, w - 1), ty = std::clamp(y0 + (t >> 1), 0, h - 1);
          const float wt = ((t & 1) ? ax : 1 - ax) * ((t >> 1) ? ay : 1 - ay);
          for (int c = 0; c < 3; ++c) hist[c] += wt * history_[c](tx, ty);
        }
        YCoCg hy = toYCoCg(hist[0], hist[1], hist[2]);
        hy = {std::clamp(hy.y, lo.y, hi.y), std::clamp(hy.co, lo.co, hi.co), std::clamp(hy.cg, lo.cg, hi.cg)};
        YCoCg blended{alpha * cur.y + (1 - alpha) * hy.y, alpha * cur.co + (1 - alpha) * hy.co,
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
