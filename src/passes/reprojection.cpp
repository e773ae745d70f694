#include "passes/reprojection.h"

#include <algorithm>
#include <cmath>
#ifdef __SSE2__
#include <immintrin.h>
#endif

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

int Reprojection::taps(size_t i, Taps& out) const {
  out.count = 0;
  if (kind[i] == Bilinear) {
    const int offsets[4] = {0, 1, width, width + 1};
    for (int t = 0; t < 4; ++t)
      if (weights[i][t] != 0.0f) {
        out.index[out.count] = base[i] + offsets[t];
        out.weight[out.count++] = weights[i][t];
      }
  } else if (kind[i] == Fallback3x3) {
    float wsum = 0.0f;
    for (int t = 0; t < 9; ++t)
      if (mask3x3[i] & (1u << t)) {
        out.index[out.count] = base[i] + (t / 3 - 1) * width + (t % 3 - 1);
        out.weight[out.count++] = kFallbackKernel3x3[t];
        wsum += kFallbackKernel3x3[t];
      }
    for (int t = 0; t < out.count; ++t) out.weight[t] /= wsum;
  }
  return out.count;
}

float Reprojection::gather3x3(const Plane& h, size_t i) const {
  Taps t;
  taps(i, t);
  return t.gather(h);
}

namespace {

// Row-major 4x4 times (x, y, z, 1).
inline void transformPoint(const std::array<float, 16>& m, float x, float y, float z, float out[4]) {
  for (int r = 0; r < 4; ++r) out[r] = m[r * 4 + 0] * x + m[r * 4 + 1] * y + m[r * 4 + 2] * z + m[r * 4 + 3];
}

// Raw pointers to the planes the tests read, hoisted out of the per-pixel loop.
struct TapTest {
  const ReprojectionSettings& s;
  const int width, height;  // of the previous frame
  const float *z = nullptr, *zPrev = nullptr, *dzdx = nullptr, *dzdy = nullptr;
  const float *n[3] = {}, *nPrev[3] = {};
  const float *id = nullptr, *idPrev = nullptr;
  const float *p[3] = {}, *pPrev[3] = {};
  float positionTolerance2;

  TapTest(const FrameData& cur, const FrameData& prev, const ReprojectionSettings& st)
      : s(st), width(prev.width), height(prev.height),
        positionTolerance2(st.positionTolerance * st.positionTolerance) {
    if (cur.has(Buffer::Depth) && prev.has(Buffer::Depth)) {
      z = cur.plane(Buffer::Depth).ptr();
      zPrev = prev.plane(Buffer::Depth).ptr();
      if (cur.has(Buffer::DepthGradient)) {
        dzdx = cur.plane(Buffer::DepthGradient, 0).ptr();
        dzdy = cur.plane(Buffer::DepthGradient, 1).ptr();
      }
    }
    if (cur.has(Buffer::Normal) && prev.has(Buffer::Normal))
      for (int c = 0; c < 3; ++c) { n[c] = cur.plane(Buffer::Normal, c).ptr(); nPrev[c] = prev.plane(Buffer::Normal, c).ptr(); }
    if (st.testObjectId && cur.has(Buffer::ObjectId) && prev.has(Buffer::ObjectId)) {
      id = cur.plane(Buffer::ObjectId).ptr();
      idPrev = prev.plane(Buffer::ObjectId).ptr();
    }
    if (st.positionTolerance > 0 && cur.has(Buffer::Position) && prev.has(Buffer::Position))
      for (int c = 0; c < 3; ++c) { p[c] = cur.plane(Buffer::Position, c).ptr(); pPrev[c] = prev.plane(Buffer::Position, c).ptr(); }
  }

  // Screen-space depth slope at pixel (x, y) of a w-wide frame: per axis the smaller one-sided
  // difference, so a depth edge next to the pixel does not widen the tolerance.
  float depthSlope(int x, int y, int w, int h) const {
    const size_t i = size_t(y) * w + x;
    if (dzdx) return std::max(std::abs(dzdx[i]), std::abs(dzdy[i]));
    const float c = z[i];
    auto slope = [&](float a, float b) { return std::min(std::abs(a - c), std::abs(b - c)); };
    const float gx = slope(z[i - (x > 0)], z[i + (x < w - 1)]);
    const float gy = slope(z[i - (y > 0) * size_t(w)], z[i + (y < h - 1) * size_t(w)]);
    return std::max(gx, gy);
  }

  // The current pixel's features, loaded once for its up to 13 tap tests.
  struct Pixel {
    float z, n[3], id, p[3], depthTol;
    bool background;  // zero normal: a miss (sky) in Cycles' and our renderer's buffers
  };
  Pixel load(size_t i, float depthTol) const {
    Pixel c{};
    if (z) c.z = z[i];
    if (n[0]) for (int k = 0; k < 3; ++k) c.n[k] = n[k][i];
    c.background = n[0] && c.n[0] * c.n[0] + c.n[1] * c.n[1] + c.n[2] * c.n[2] < 0.25f;
    if (id) c.id = id[i];
    if (p[0]) for (int k = 0; k < 3; ++k) c.p[k] = p[k][i];
    c.depthTol = depthTol;
    return c;
  }

  // Validity of the four taps j, j+1, j+w, j+w+1 of an interior bilinear footprint at once
  // (the common case), one SSE lane per tap: the same tests as valid(), as a lane mask.
  typedef float F4 __attribute__((vector_size(16)));
  typedef int I4 __attribute__((vector_size(16)));
  static F4 quad(const float* p, size_t j, int w) {
#ifdef __SSE2__
    // Two 8-byte loads straight into the register halves (a memcpy into a vector goes through
    // the stack and stalls on store forwarding).
    const __m128d v = _mm_loadh_pd(_mm_load_sd(reinterpret_cast<const double*>(p + j)),
                                   reinterpret_cast<const double*>(p + j + w));
    return F4(_mm_castpd_ps(v));
#else
    return F4{p[j], p[j + 1], p[j + w], p[j + w + 1]};
#endif
  }
  I4 validQuad(const Pixel& c, size_t j) const {
    I4 ok = I4{} == 0;  // all lanes true
    if (z) {
      const F4 dz = quad(zPrev, j, width) - c.z;
      ok &= (dz <= c.depthTol) & (dz >= -c.depthTol);
    }
    if (n[0]) {
      const F4 qx = quad(nPrev[0], j, width), qy = quad(nPrev[1], j, width), qz = quad(nPrev[2], j, width);
      if (c.background) ok &= qx * qx + qy * qy + qz * qz < 0.25f;
      else ok &= c.n[0] * qx + c.n[1] * qy + c.n[2] * qz >= s.normalTolerance;
    }
    if (id) ok &= quad(idPrev, j, width) == c.id;
    if (p[0]) {
      const F4 dx = c.p[0] - quad(pPrev[0], j, width), dy = c.p[1] - quad(pPrev[1], j, width),
               dz = c.p[2] - quad(pPrev[2], j, width);
      ok &= dx * dx + dy * dy + dz * dz <= positionTolerance2;
    }
    return ok;
  }

  // Is previous pixel (px, py) a valid history sample for the current pixel c?
  bool valid(const Pixel& c, int px, int py) const {
    if (px < 0 || py < 0 || px >= width || py >= height) return false;
    const size_t j = size_t(py) * width + px;
    if (z && !(std::abs(zPrev[j] - c.z) <= c.depthTol)) return false;
    if (n[0]) {
      // Background pixels (zero normal) match background pixels only.
      if (c.background) {
        if (!(nPrev[0][j] * nPrev[0][j] + nPrev[1][j] * nPrev[1][j] + nPrev[2][j] * nPrev[2][j] < 0.25f)) return false;
      } else if (!(c.n[0] * nPrev[0][j] + c.n[1] * nPrev[1][j] + c.n[2] * nPrev[2][j] >= s.normalTolerance)) {
        return false;
      }
    }
    if (id && c.id != idPrev[j]) return false;
    if (p[0]) {
      const float dx = c.p[0] - pPrev[0][j], dy = c.p[1] - pPrev[1][j], dz = c.p[2] - pPrev[2][j];
      if (!(dx * dx + dy * dy + dz * dz <= positionTolerance2)) return false;
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
  const float* motionX = motion ? cur.plane(Buffer::Motion, 0).ptr() : nullptr;
  const float* motionY = motion ? cur.plane(Buffer::Motion, 1).ptr() : nullptr;

  parallelRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      // Continuous previous position of this pixel's centre.
      float px = x + 0.5f, py = y + 0.5f;
      if (motion) {
        px += motionX[i];
        py += motionY[i];
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

      const TapTest::Pixel pixel =
          test.load(i, test.z ? s.depthTolerance * test.z[i] + s.depthGradientScale * test.depthSlope(x, y, w, h) : 0.0f);
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
      if (x0 >= 0 && y0 >= 0 && x0 < w - 1 && y0 < h - 1) {
        const TapTest::F4 b{bw[0], bw[1], bw[2], bw[3]};
        const TapTest::F4 v = test.validQuad(pixel, size_t(y0) * w + x0) ? b : TapTest::F4{};
        for (int t = 0; t < 4; ++t) { wt[t] = v[t]; sum += v[t]; }
      } else {
        for (int t = 0; t < 4; ++t)
          if (bw[t] > 0.0f && test.valid(pixel, tx[t], ty[t])) { wt[t] = bw[t]; sum += bw[t]; }
      }
      if (sum > 1e-4f && w >= 2 && h >= 2) {
        for (auto& v : wt) v /= sum;
        // Taps outside the image have weight 0; slide the 2x2 window inside (moving the weights
        // with it) so gathers can read all four taps without bounds checks.
        int bx = x0, by = y0;
        if (bx < 0) { bx = 0; wt = {wt[1], 0.0f, wt[3], 0.0f}; }
        if (bx > w - 2) { bx = w - 2; wt = {0.0f, wt[0], 0.0f, wt[2]}; }
        if (by < 0) { by = 0; wt = {wt[2], wt[3], 0.0f, 0.0f}; }
        if (by > h - 2) { by = h - 2; wt = {0.0f, 0.0f, wt[0], wt[1]}; }
        out.kind[i] = Reprojection::Bilinear;
        out.base[i] = by * w + bx;
        out.weights[i] = wt;
        continue;
      }
      if (!s.fallback3x3) continue;
      const int cx = int(std::floor(px)), cy = int(std::floor(py));
      uint16_t mask = 0;
      for (int t = 0; t < 9; ++t)
        if (test.valid(pixel, cx + t % 3 - 1, cy + t / 3 - 1)) mask |= uint16_t(1u << t);
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
