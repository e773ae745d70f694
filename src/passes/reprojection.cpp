#include "passes/reprojection.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace rtd {

const float kFallbackKernel3x3[9] = {0.0778f, 0.1233f, 0.0778f, 0.1233f, 0.1953f,
                                     0.1233f, 0.0778f, 0.1233f, 0.0778f};

void Reprojection::resize(int w, int h) {
  width = w;
  height = h;
  const size_t n = size_t(w) * h;
  kind.assign(n, None);
  base.assign(n, 0);
  weights.assign(n, {0, 0, 0, 0});
  mask3x3.assign(n, 0);
  prevX.resize(w, h);
  prevY.resize(w, h);
}

std::array<size_t, 3> Reprojection::counts() const {
  std::array<size_t, 3> c{0, 0, 0};
  for (uint8_t k : kind) ++c[k];
  return c;
}

float Reprojection::gather3x3(const Plane& h, size_t i) const {
  const uint16_t m = mask3x3[i];
  float sum = 0.0f, wsum = 0.0f;
  for (int t = 0; t < 9; ++t) {
    if (!(m & (1u << t))) continue;
    const int j = base[i] + (t / 3 - 1) * h.width + (t % 3 - 1);
    sum += kFallbackKernel3x3[t] * h.ptr()[j];
    wsum += kFallbackKernel3x3[t];
  }
  return sum / wsum;
}

namespace {

// Row-major 4x4 times (x, y, z, 1).
inline void transformPoint(const std::array<float, 16>& m, float x, float y, float z, float out[4]) {
  for (int r = 0; r < 4; ++r) out[r] = m[r * 4 + 0] * x + m[r * 4 + 1] * y + m[r * 4 + 2] * z + m[r * 4 + 3];
}

struct TapTest {
  const FrameData& cur;
  const FrameData& prev;
  const ReprojectionSettings& s;
  bool depth, normal, id, position;

  TapTest(const FrameData& c, const FrameData& p, const ReprojectionSettings& st)
      : cur(c), prev(p), s(st),
        depth(c.has(Buffer::Depth) && p.has(Buffer::Depth)),
        normal(c.has(Buffer::Normal) && p.has(Buffer::Normal)),
        id(st.testObjectId && c.has(Buffer::ObjectId) && p.has(Buffer::ObjectId)),
        position(st.positionTolerance > 0 && c.has(Buffer::Position) && p.has(Buffer::Position)) {}

  // Screen-space depth slope at pixel (x, y): the smaller one-sided difference per axis, so a
  // depth edge next to the pixel does not widen the tolerance.
  float depthSlope(int x, int y) const {
    if (cur.has(Buffer::DepthGradient))
      return std::max(std::abs(cur.plane(Buffer::DepthGradient, 0)(x, y)),
                      std::abs(cur.plane(Buffer::DepthGradient, 1)(x, y)));
    const Plane& z = cur.plane(Buffer::Depth);
    const float c = z(x, y);
    auto slope = [&](float a, float b) { return std::min(std::abs(a - c), std::abs(b - c)); };
    float gx = slope(z(std::max(x - 1, 0), y), z(std::min(x + 1, z.width - 1), y));
    float gy = slope(z(x, std::max(y - 1, 0)), z(x, std::min(y + 1, z.height - 1)));
    return std::max(gx, gy);
  }

  // Is previous pixel (px, py) a valid history sample for current pixel i?
  bool valid(size_t i, int px, int py, float depthTol) const {
    if (px < 0 || py < 0 || px >= prev.width || py >= prev.height) return false;
    const size_t j = size_t(py) * prev.width + px;
    if (depth) {
      const float z = cur.plane(Buffer::Depth).data[i], zp = prev.plane(Buffer::Depth).data[j];
      if (!(std::abs(zp - z) <= depthTol)) return false;
    }
    if (normal) {
      float d = 0.0f;
      for (int c = 0; c < 3; ++c) d += cur.plane(Buffer::Normal, c).data[i] * prev.plane(Buffer::Normal, c).data[j];
      if (!(d >= s.normalTolerance)) return false;
    }
    if (id && cur.plane(Buffer::ObjectId).data[i] != prev.plane(Buffer::ObjectId).data[j]) return false;
    if (position) {
      float d2 = 0.0f;
      for (int c = 0; c < 3; ++c) {
        float d = cur.plane(Buffer::Position, c).data[i] - prev.plane(Buffer::Position, c).data[j];
        d2 += d * d;
      }
      if (!(d2 <= s.positionTolerance * s.positionTolerance)) return false;
    }
    return true;
  }
};

}  // namespace

void reproject(const FrameData& cur, const FrameData* previous, const ReprojectionSettings& s, Reprojection& out) {
  const int w = cur.width, h = cur.height;
  if (out.width != w || out.height != h) out.resize(w, h);
  if (!previous || previous->width != w || previous->height != h) {
    std::fill(out.kind.begin(), out.kind.end(), Reprojection::None);
    parallelRows(h, [&](int y) {
      for (int x = 0; x < w; ++x) { out.prevX(x, y) = x + 0.5f; out.prevY(x, y) = y + 0.5f; }
    });
    return;
  }
  const FrameData& prev = *previous;
  const bool motion = cur.has(Buffer::Motion);
  const bool fromCamera = !motion && cur.camera.valid && prev.camera.valid && cur.has(Buffer::Position);
  const TapTest test(cur, prev, s);

  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      // Continuous previous position of this pixel's centre.
      float px = x + 0.5f, py = y + 0.5f;
      if (motion) {
        px += cur.plane(Buffer::Motion, 0).data[i];
        py += cur.plane(Buffer::Motion, 1).data[i];
      } else if (fromCamera) {
        float v[4], c[4];
        transformPoint(prev.camera.worldToCamera, cur.plane(Buffer::Position, 0).data[i],
                       cur.plane(Buffer::Position, 1).data[i], cur.plane(Buffer::Position, 2).data[i], v);
        transformPoint(prev.camera.projection, v[0], v[1], v[2], c);
        if (c[3] > 0.0f) {
          px = (c[0] / c[3] * 0.5f + 0.5f) * w;
          py = (0.5f - c[1] / c[3] * 0.5f) * h;  // NDC y is up, rows go down
        } else {
          px = py = -1e6f;  // behind the previous camera
        }
      }
      out.prevX.data[i] = px;
      out.prevY.data[i] = py;

      const float depthTol = test.depth ? s.depthTolerance * cur.plane(Buffer::Depth).data[i] +
                                              s.depthGradientScale * test.depthSlope(x, y)
                                        : 0.0f;
      // Bilinear footprint: taps are pixel centres, so the top-left tap is floor(p - 0.5).
      const float fx = px - 0.5f, fy = py - 0.5f;
      out.kind[i] = Reprojection::None;
      if (!(std::abs(fx) < 1e6f && std::abs(fy) < 1e6f)) continue;
      const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
      const float ax = fx - x0, ay = fy - y0;
      const float bw[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
      const int tx[4] = {x0, x0 + 1, x0, x0 + 1}, ty[4] = {y0, y0, y0 + 1, y0 + 1};
      float sum = 0.0f;
      std::array<float, 4> wt{0, 0, 0, 0};
      for (int t = 0; t < 4; ++t)
        if (bw[t] > 0.0f && test.valid(i, tx[t], ty[t], depthTol)) { wt[t] = bw[t]; sum += bw[t]; }
      if (sum > 1e-4f) {
        for (auto& v : wt) v /= sum;
        out.kind[i] = Reprojection::Bilinear;
        // Taps of weight 0 may be outside; base stays the top-left tap index (may be negative
        // offsets only through zero-weight taps, which gather() never reads).
        out.base[i] = y0 * w + x0;
        out.weights[i] = wt;
        continue;
      }
      if (!s.fallback3x3) continue;
      const int cx = int(std::floor(px)), cy = int(std::floor(py));
      uint16_t mask = 0;
      for (int t = 0; t < 9; ++t)
        if (test.valid(i, cx + t % 3 - 1, cy + t / 3 - 1, depthTol)) mask |= uint16_t(1u << t);
      if (mask) {
        out.kind[i] = Reprojection::Fallback3x3;
        out.base[i] = cy * w + cx;
        out.mask3x3[i] = mask;
      }
    }
  });
}

void updateHistoryLength(const Reprojection& rp, const Plane& previousLength, int maxLength, Plane& length) {
  const int w = rp.width;
  parallelRows(rp.height, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      float n = rp.kind[i] == Reprojection::None ? 0.0f : std::round(rp.gather(previousLength, i));
      length.data[i] = std::min(n + 1.0f, float(maxLength));
    }
  });
}

}  // namespace rtd
