// reprojectRows for one CPU path (core/simd.h): the tap tests of kLanes pixels at a time on the
// avx2 and avx512 paths (8 and 16 lanes); the scalar path, which stays the reference,
// for borders, disocclusions, the 3x3 fallback and the sse2 path.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "passes/reprojection.h"
#include "core/simd.h"
#include "passes/shifted_footprints.h"

namespace rtd::RTD_SIMD_NS {

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

  TapTest(const FrameData& cur, const FrameData& prev, const ReprojectionSettings& st)
      : s(st), width(prev.width), height(prev.height) {
    if (st.testDepth && cur.has(Buffer::Depth) && prev.has(Buffer::Depth)) {
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
    if (st.testsPosition() && cur.has(Buffer::Position) && prev.has(Buffer::Position))
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

  // Squared position tolerance of pixel (x, y): positionTolerance + positionFootprints times
  // its world-space footprint, per axis the smaller one-sided distance to the neighbour's world
  // position (the other side only at the frame's border), the larger of the two axes. The
  // footprint is distance x pixel angle / cos(incidence), so it scales with the scene.
  float positionTolerance2(int x, int y, int w, int h) const {
    const size_t i = size_t(y) * w + x;
    auto d2 = [&](size_t j) {
      const float dx = p[0][j] - p[0][i], dy = p[1][j] - p[1][i], dz = p[2][j] - p[2][i];
      return dx * dx + dy * dy + dz * dz;
    };
    auto side = [](int v, int d, int n) { return std::clamp(v + d >= 0 && v + d < n ? v + d : v - d, 0, n - 1); };
    const size_t row = size_t(y) * w;
    const size_t left = row + side(x, -1, w), right = row + side(x, 1, w);
    const size_t up = size_t(side(y, -1, h)) * w + x, down = size_t(side(y, 1, h)) * w + x;
    const float f2 = std::max(std::min(d2(left), d2(right)), std::min(d2(up), d2(down)));
    const float tol = s.positionTolerance + s.positionFootprints * std::sqrt(f2);
    return tol * tol;
  }

  // The current pixel's features, loaded once for its up to 13 tap tests.
  struct Pixel {
    float z, n[3], id, p[3], depthTol, positionTol2;
    bool background;  // zero normal: a miss (sky) in Cycles' and our renderer's buffers
  };
  Pixel load(size_t i, float depthTol, float positionTol2) const {
    Pixel c{};
    if (z) c.z = z[i];
    if (n[0]) for (int k = 0; k < 3; ++k) c.n[k] = n[k][i];
    c.background = n[0] && c.n[0] * c.n[0] + c.n[1] * c.n[1] + c.n[2] * c.n[2] < 0.25f;
    if (id) c.id = id[i];
    if (p[0]) for (int k = 0; k < 3; ++k) c.p[k] = p[k][i];
    c.depthTol = depthTol;
    c.positionTol2 = positionTol2;
    return c;
  }

  // Depth tolerance of pixel (x, y): relative plus screen-space slope.
  float depthTolerance(int x, int y, int w, int h) const {
    return s.depthTolerance * z[size_t(y) * w + x] + s.depthGradientScale * depthSlope(x, y, w, h);
  }

#ifdef RTD_SIMD_AVX2
  // How the lanes' footprints lie (bilinearLanes): consecutive (vector loads), shifted by at
  // most one column and one row from consecutive (passes/shifted_footprints.h), or anywhere
  // (gathers).
  enum class Layout { consecutive, shifted, scattered };

  // Pixels x..x+kLanes-1 of row y (x + kLanes <= w; a row's end takes the scalar tests'
  // one-sided neighbours) whose four bilinear taps all lie inside the previous frame: the tests
  // of valid() on kLanes pixels at once (8 on avx2, 16 on avx512), the four taps of each read
  // with vector loads where the footprints are consecutive, as selections between loads where
  // they are shifted (passes/shifted_footprints.h), with gathers otherwise. Writes kind, base
  // and weights of the lanes with a valid tap (sum of accepted bilinear weights > 1e-4) and
  // returns their bit mask; the other lanes are left to the caller. The tests a frame has (kZ
  // depth, kN normal, kId object id, kP position; the pointers above) are template arguments,
  // so the four taps unroll with the features in registers (a run-time test per feature and
  // tap kept the loop rolled and spilled the features; docs/performance.md, "Session 12").
  template <bool kZ, bool kN, bool kId, bool kP>
  uint32_t bilinearLanes(int x, int y, int w, int h, Reprojection& out) const {
    using RTD_SIMD_NS::load;  // the vector load, not Pixel load()
    const size_t i = size_t(y) * w + x;
    // The bilinear footprints: taps are pixel centres, so the top-left tap is floor(p - 0.5)
    // (setBilinear); a lane with any tap off the frame sends the group to the scalar path.
    const vf fx = load(out.prevX.ptr() + i) - 0.5f, fy = load(out.prevY.ptr() + i) - 0.5f;
    const vf flx = vfloor(fx), fly = vfloor(fy);
    if (!allTrue((flx >= 0.0f) & (flx < float(w - 1)) & (fly >= 0.0f) & (fly < float(h - 1)))) return 0;
    const vf ax = fx - flx, ay = fy - fly, bx = 1.0f - ax, by = 1.0f - ay;
    const vf bilinear[4] = {bx * by, ax * by, bx * ay, ax * ay};
    const vi base = __builtin_convertvector(fly, vi) * w + __builtin_convertvector(flx, vi);
    {
      // The previous frame's two tap rows and the current frame's planes ahead (kPrefetchAhead).
      const size_t b0 = size_t(base[0]);
      auto previous = [&](const float* q) { prefetchAhead(q + b0), prefetchAhead(q + b0 + w); };
      auto current = [&](const float* q) { prefetchAhead(q + i); };
      if constexpr (kZ) {
        previous(zPrev), current(z);
        if (dzdx) current(dzdx), current(dzdy);
      }
      if constexpr (kN)
        for (int k = 0; k < 3; ++k) previous(nPrev[k]), current(n[k]);
      if constexpr (kId) previous(idPrev), current(id);
      if constexpr (kP)
        for (int k = 0; k < 3; ++k) previous(pPrev[k]), current(p[k]);
    }
    ShiftedFootprints shifted;
    if (allTrue(base == base[0] + laneIndex())) return bilinearTaps<kZ, kN, kId, kP, Layout::consecutive>(bilinear, base, shifted, i, y, w, h, out);
    if (shifted.classify(__builtin_convertvector(flx, vi), __builtin_convertvector(fly, vi), w, size_t(width) * height, 2, 2))
      return bilinearTaps<kZ, kN, kId, kP, Layout::shifted>(bilinear, base, shifted, i, y, w, h, out);
    return bilinearTaps<kZ, kN, kId, kP, Layout::scattered>(bilinear, base, shifted, i, y, w, h, out);
  }

  template <bool kZ, bool kN, bool kId, bool kP, Layout kLayout>
  uint32_t bilinearTaps(const vf (&bilinear)[4], vi base, const ShiftedFootprints& shifted, size_t i, int y, int w, int h,
                        Reprojection& out) const {
    using RTD_SIMD_NS::load;
    // Tap t (0 top left, 1 top right, 2 bottom left, 3 bottom right) of plane q.
    auto fetch = [&](const float* q, int t) __attribute__((always_inline)) {
      const float* o = q + (t & 1) + (t >> 1) * w;
      if constexpr (kLayout == Layout::consecutive) {
        return load(o + base[0]);
      } else if constexpr (kLayout == Layout::shifted) {
        return shifted.tap(q, t & 1, t >> 1, w);
      } else {
        return vgather(o, base);
      }
    };
    // The row neighbours (dx = -1, 1) of plane q's values `centre` at the group's pixels: at a
    // row's end the pixel itself (`self`: the depth slope's one-sided difference) or the
    // neighbour on the other side (the position footprint's), as the scalar tests.
    const bool atLeft = i == size_t(y) * w, atRight = i + kLanes == size_t(y + 1) * w;
    auto rowNeighbour = [&](const float* q, vf centre, int dx, bool self) __attribute__((always_inline)) {
      if (dx < 0 ? !atLeft : !atRight) return load(q + i + dx);
      const int end = dx < 0 ? 0 : kLanes - 1;  // the lane at the row's end
      const vi index = laneIndex() == end ? vi{} + (self ? end : end - dx) : laneIndex() + dx;
      return vpermute2(centre, centre, index);
    };
    // The current pixels' features.
    vf tol{}, cz{}, cn[3] = {}, cid{}, cp[3] = {}, positionTol2{};
    vi background{};
    if constexpr (kZ) {
      cz = load(z + i);
      vf slope;
      if (dzdx) {
        slope = vmax(vabs(load(dzdx + i)), vabs(load(dzdy + i)));
      } else {
        auto diff = [&](vf v) { return vabs(v - cz); };
        const float* up = z + i - (y > 0 ? size_t(w) : 0);
        const float* down = z + i + (y < h - 1 ? size_t(w) : 0);
        slope = vmax(vmin(diff(rowNeighbour(z, cz, -1, true)), diff(rowNeighbour(z, cz, 1, true))),
                     vmin(diff(load(up)), diff(load(down))));
      }
      tol = s.depthTolerance * cz + s.depthGradientScale * slope;
    }
    if constexpr (kN) {
      for (int k = 0; k < 3; ++k) cn[k] = load(n[k] + i);
      background = cn[0] * cn[0] + cn[1] * cn[1] + cn[2] * cn[2] < 0.25f;
    }
    if constexpr (kId) cid = load(id + i);
    if constexpr (kP) {
      for (int k = 0; k < 3; ++k) cp[k] = load(p[k] + i);
      // positionTolerance2(): the other side's neighbour at the frame's border.
      const size_t up = y > 0 ? i - w : i + w, down = y < h - 1 ? i + w : i - w;
      auto d2 = [&](auto neighbour) {
        vf r{};
        for (int k = 0; k < 3; ++k) {
          const vf d = neighbour(k) - cp[k];
          r += d * d;
        }
        return r;
      };
      auto row = [&](int dx) { return [&, dx](int k) { return rowNeighbour(p[k], cp[k], dx, false); }; };
      auto column = [&](size_t j) { return [&, j](int k) { return load(p[k] + j); }; };
      const vf f2 = vmax(vmin(d2(row(-1)), d2(row(1))), vmin(d2(column(up)), d2(column(down))));
      const vf t = s.positionTolerance + s.positionFootprints * vsqrt(f2);
      positionTol2 = t * t;
    }
    const vf minusTol = 0.0f - tol;

    vf wt[4], sum{};
#pragma GCC unroll 4
    for (int t = 0; t < 4; ++t) {
      vi ok = vi{} == 0;
      if constexpr (kZ) {
        const vf dz = fetch(zPrev, t) - cz;
        ok &= (dz <= tol) & (dz >= minusTol);
      }
      if constexpr (kN) {
        const vf qx = fetch(nPrev[0], t), qy = fetch(nPrev[1], t), qz = fetch(nPrev[2], t);
        // Background pixels (zero normal) match background pixels only.
        const vi bgOk = qx * qx + qy * qy + qz * qz < 0.25f;
        const vi fgOk = cn[0] * qx + cn[1] * qy + cn[2] * qz >= s.normalTolerance;
        ok &= background ? bgOk : fgOk;
      }
      if constexpr (kId) ok &= fetch(idPrev, t) == cid;
      if constexpr (kP) {
        vf d2{};
        for (int k = 0; k < 3; ++k) {
          const vf d = cp[k] - fetch(pPrev[k], t);
          d2 += d * d;
        }
        ok &= d2 <= positionTol2;
      }
      wt[t] = keepIf(ok, bilinear[t]);
      sum += wt[t];
    }
    const vi accepted = sum > 1e-4f;
    const uint32_t good = laneBits(accepted);
    if (!good) return 0;
    for (auto& v : wt) v /= sum;
    float* weights = out.weights[i].data();
    if (allTrue(accepted)) {
      storeInterleaved4(wt, weights);
      std::memcpy(out.base.data() + i, &base, sizeof base);
      std::memset(out.kind.data() + i, Reprojection::Bilinear, kLanes);
      return good;
    }
    for (int k = 0; k < kLanes; ++k)
      if (good >> k & 1u) {
        for (int t = 0; t < 4; ++t) weights[4 * k + t] = wt[t][k];
        out.base[i + k] = base[k];
        out.kind[i + k] = Reprojection::Bilinear;
      }
    return good;
  }

  // The per-pixel {w0, w1, w2, w3} layout of four tap vectors, eight lanes at a time.
  static void storeInterleaved4(const vf (&wt)[4], float* out) {
    auto store8 = [](const __m256 (&c)[4], float* o) {
      __m256 packed[4];
      interleave4x8(c, packed);
      for (int m = 0; m < 4; ++m) _mm256_storeu_ps(o + 8 * m, packed[m]);
    };
#ifdef RTD_SIMD_AVX512
    const __m256 lo[4] = {_mm512_castps512_ps256(wt[0]), _mm512_castps512_ps256(wt[1]), _mm512_castps512_ps256(wt[2]),
                          _mm512_castps512_ps256(wt[3])};
    const __m256 hi[4] = {_mm512_extractf32x8_ps(wt[0], 1), _mm512_extractf32x8_ps(wt[1], 1),
                          _mm512_extractf32x8_ps(wt[2], 1), _mm512_extractf32x8_ps(wt[3], 1)};
    store8(lo, out);
    store8(hi, out + 32);
#else
    const __m256 c[4] = {wt[0], wt[1], wt[2], wt[3]};
    store8(c, out);
#endif
  }
#endif

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
      if (!(dx * dx + dy * dy + dz * dz <= c.positionTol2)) return false;
    }
    return true;
  }
};

}  // namespace

#ifdef RTD_SIMD_AVX2
// Where the row's vector groups start. On avx512 at its first pixel, so that the current
// frame's planes are read with aligned loads (from the second, every 64-byte load straddled two
// cache lines; BM_Reproject 0.90, BMFR's tests 0.85). On avx2, where every other 32-byte load
// straddles, the two starts differed by the test set (BM_Reproject 1.10-1.15 from the first
// pixel, BMFR's tests 0.90), so it keeps the second.
constexpr int kFirstGroup = kLanes == 16 ? 0 : 1;
#endif

void reprojectRows(const FrameData& cur, const FrameData* previous, const ReprojectionSettings& s, Reprojection& out,
                   int rowBegin, int rowEnd) {
  const int w = cur.width, h = cur.height;
  if (!previous || previous->width != w || previous->height != h) {
    for (int y = rowBegin; y < rowEnd; ++y)
      for (int x = 0; x < w; ++x) {
        out.kind[size_t(y) * w + x] = Reprojection::None;
        out.prevX(x, y) = x + 0.5f;
        out.prevY(x, y) = y + 0.5f;
      }
    return;
  }
  const FrameData& prev = *previous;
  const bool motion = cur.has(Buffer::Motion);
  const bool fromCamera = !motion && cur.camera.valid && prev.camera.valid && cur.has(Buffer::Position);
  const TapTest test(cur, prev, s);
  // Pixels without geometry (zero normal, as TapTest::Pixel::background) see the sky.
  const float* normal[3] = {};
  if (fromCamera && cur.has(Buffer::Normal))
    for (int c = 0; c < 3; ++c) normal[c] = cur.plane(Buffer::Normal, c).ptr();
  std::array<float, 12> curDirections{}, prevDirections{};
  if (normal[0]) curDirections = directionToClip(cur.camera), prevDirections = directionToClip(prev.camera);
  const float* motionX = motion ? cur.plane(Buffer::Motion, 0).ptr() : nullptr;
  const float* motionY = motion ? cur.plane(Buffer::Motion, 1).ptr() : nullptr;

  // One pixel, scalar: any footprint, the border slide and the 3x3 fallback.
  auto classify = [&](int x, int y) {
    const size_t i = size_t(y) * w + x;
    const float px = out.prevX.data[i], py = out.prevY.data[i];
    const TapTest::Pixel pixel = test.load(i, test.z ? test.depthTolerance(x, y, w, h) : 0.0f,
                                           test.p[0] ? test.positionTolerance2(x, y, w, h) : 0.0f);
    out.kind[i] = Reprojection::None;
    if (!(std::abs(px) < 1e6f && std::abs(py) < 1e6f)) return;
    // valid() checks the frame bounds itself.
    if (setBilinear(out, i, px, py, [&](int tx, int ty) { return test.valid(pixel, tx, ty); })) return;
    if (!s.fallback3x3) return;
    const int cx = int(std::floor(px)), cy = int(std::floor(py));
    uint16_t mask = 0;
    for (int t = 0; t < 9; ++t)
      if (test.valid(pixel, cx + t % 3 - 1, cy + t / 3 - 1)) mask |= uint16_t(1u << t);
    if (mask) {
      out.kind[i] = Reprojection::Fallback3x3;
      out.base[i] = cy * w + cx;
      out.mask3x3[i] = mask;
    }
  };

  for (int y = rowBegin; y < rowEnd; ++y) {
    // Continuous previous position of each pixel's centre (the common motion-vector case in
    // its own loop, which vectorizes).
    float* prevX = out.prevX.row(y);
    float* prevY = out.prevY.row(y);
    const size_t row = size_t(y) * w;
    if (motion) {
      for (int x = 0; x < w; ++x) {
        prevX[x] = float(x) + 0.5f + motionX[row + x];
        prevY[x] = float(y) + 0.5f + motionY[row + x];
      }
    } else {
      for (int x = 0; x < w; ++x) {
        float px = x + 0.5f, py = y + 0.5f;
        const size_t i = row + x;
        const bool sky = normal[0] && normal[0][i] * normal[0][i] + normal[1][i] * normal[1][i] + normal[2][i] * normal[2][i] < 0.25f;
        if (sky) {
          if (!reprojectDirection(curDirections, prevDirections, px, py, w, h, px, py)) px = py = -1e6f;
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
        prevX[x] = px;
        prevY[x] = py;
      }
    }
    int x = 0;
#ifdef RTD_SIMD_AVX2
    // kLanes pixels at a time where every footprint is inside the frame (the common case);
    // lanes with no valid bilinear tap go through the scalar path. From kFirstGroup.
    if (w >= kLanes + kFirstGroup) {
      for (x = 0; x < kFirstGroup; ++x) classify(x, y);
      auto groups = [&](auto kZ, auto kN, auto kId, auto kP) {
        for (x = kFirstGroup; x + kLanes <= w; x += kLanes) {
          const uint32_t bilinear =
              test.bilinearLanes<decltype(kZ)::value, decltype(kN)::value, decltype(kId)::value, decltype(kP)::value>(
                  x, y, w, h, out);
          for (int k = 0; k < kLanes; ++k)
            if (!(bilinear >> k & 1u)) classify(x + k, y);
        }
      };
      // One instantiation per combination of the tests the frame has.
      using T = std::true_type;
      using F = std::false_type;
      auto withP = [&](auto kZ, auto kN, auto kId) { test.p[0] ? groups(kZ, kN, kId, T{}) : groups(kZ, kN, kId, F{}); };
      auto withId = [&](auto kZ, auto kN) { test.id ? withP(kZ, kN, T{}) : withP(kZ, kN, F{}); };
      auto withN = [&](auto kZ) { test.n[0] ? withId(kZ, T{}) : withId(kZ, F{}); };
      test.z ? withN(T{}) : withN(F{});
    }
#endif
    for (; x < w; ++x) classify(x, y);
  }
}

}  // namespace rtd::RTD_SIMD_NS
