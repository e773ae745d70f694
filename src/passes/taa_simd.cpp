// TAA's rows for one CPU path (core/simd.h): the history fetch (bilinear: Bilinear8, eight
// pixels at a time; Catmull-Rom: catmullRomFetchLanes, 8 or 16) on the avx2 and avx512 paths,
// pixel by pixel on sse2 and at the frame's border; the clamp and blend loop is vectorized by
// the compiler for each path's width.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>

#include "core/flush.h"
#include "passes/taa_kernels.h"
#include "passes/tonemap.h"
#include "core/simd.h"
#include "passes/bilinear8.h"
#include "passes/shifted_footprints.h"

namespace rtd::RTD_SIMD_NS {

namespace {

inline float fmin(float a, float b) { return a < b ? a : b; }
inline float fmax(float a, float b) { return a > b ? a : b; }

// Catmull-Rom weights of the taps at -1, 0, 1, 2 for the fraction t in [0, 1): Keys' cubic
// convolution kernel with a = -1/2 (Keys 1981, Eq. 15), written out per tap. They sum to 1
// and reproduce quadratics. A weight below 2^-24 in magnitude is 0 (it is below the float
// rounding of the sum, whose two middle weights add up to at least 1): with stored values
// >= kTiny their products stay normal (core/flush.h). The GLSL twin is in taa.comp.
inline void catmullRomWeights(float t, float w[4]) {
  w[0] = 0.5f * t * ((2.0f - t) * t - 1.0f);
  w[1] = 0.5f * (t * t * (3.0f * t - 5.0f) + 2.0f);
  w[2] = 0.5f * t * ((4.0f - 3.0f * t) * t + 1.0f);
  w[3] = 0.5f * t * t * (t - 1.0f);
  for (int k = 0; k < 4; ++k) w[k] = std::abs(w[k]) < 0x1p-24f ? 0.0f : w[k];
}

// The Catmull-Rom history of the three planes at (px, py) (pixel units, texel centres at
// integers): the separable 4x4 cubic, rows summed first. Taps off the frame repeat the border
// texel (clamp-to-edge addressing, as a texture sampler's), so a footprint crossing the border
// extrapolates the border value flat. Only the result is flushed (core/flush.h), not each row's
// sum: a row's terms are 0 or >= 2^-84 (weights >= 2^-24, stored values >= kTiny), so a sum
// whose product with a weight >= 2^-24 could be subnormal (below 2^-102) needs its terms to
// cancel to below 2^-18 of their size; no underflow of small weights or fading values leads
// there, as it did in the a-trous weights (issue 20). The four row flushes were a third of the
// fetch's operations: without them BM_Taa on sse2 0.90; on avx2 and avx512, whose fetch waits
// on memory, within the noise (docs/performance.md, "Session 21"). taa.comp never had them.
inline void catmullRomFetch(const Plane3& hist, float px, float py, int w, int h, float v[3]) {
  const float fx = std::floor(px), fy = std::floor(py);
  const int x0 = int(fx) - 1, y0 = int(fy) - 1;
  float wx[4], wy[4];
  catmullRomWeights(px - fx, wx);
  catmullRomWeights(py - fy, wy);
  int xs[4], ys[4];
  for (int k = 0; k < 4; ++k) {
    xs[k] = std::clamp(x0 + k, 0, w - 1);
    ys[k] = std::clamp(y0 + k, 0, h - 1);
  }
  for (int c = 0; c < 3; ++c) {
    float sum = 0.0f;
    for (int j = 0; j < 4; ++j) {
      const float* row = hist[c].row(ys[j]);
      const float r = wx[0] * row[xs[0]] + wx[1] * row[xs[1]] + wx[2] * row[xs[2]] + wx[3] * row[xs[3]];
      sum += wy[j] * r;
    }
    v[c] = flushTiny(sum);
  }
}

// Display encoding (tonemap::taaEncode) of n values, kLanes at a time: sqrt(q), q = v / (1 + v),
// from the reciprocal and square-root estimates, each refined by a Newton step (vrcp, vrsqrt;
// ~1e-7 relative), where a division and a square root cost ~60 cycles of the divider per 16
// lanes (the pass 5-10 % faster on one thread; docs/performance.md, "Session 10").
inline vf encodeLanes(vf v) {
  v = vmin(vmax(v, splat(0.0f)), splat(1e30f));  // NaN -> 0, as taaEncode
  const vf q = v * vrcp(1.0f + v);
  return keepIf(q > 0.0f, q * vrsqrt(q));  // sqrt(q) = q / sqrt(q); sqrt(0) = 0
}
void encodeRow(const float* in, float* out, int n) {
  int x = 0;
  for (; x + kLanes <= n; x += kLanes) {
    prefetchAhead(in + x);
    store(out + x, encodeLanes(load(in + x)));
  }
  for (; x < n; ++x) out[x] = tonemap::taaEncode(in[x]);
}
// tonemap::taaDecode of an encoded history value in [0, kTaaMaxEncoded], in the blend loop's
// scalar tail and the own-surface box (the vector loop decodes by vrcp, from registers: decoding
// the rows afterwards waited on reloading them). taaDecode's clamp is the blend's display bound
// `top`, which buildSlot caps at kTaaMaxEncoded.
inline float decode(float y) {
  const float t = y * y;
  return t / (1.0f - t);
}

// YCoCg of row y (of its display encoding with kDisplay) and its horizontal 3-tap min/max
// (border pixel repeated) into `slot`; with kDisplay also the horizontal 3-tap max of the
// largest encoded channel, which bounds the decoded output.
template <bool kDisplay> void buildSlot(const Plane3& color, int y, int w, float* slot) {
  const float *r = color[0].row(y), *g = color[1].row(y), *b = color[2].row(y);
  float* c[3] = {slot, slot + w, slot + 2 * w};
  if constexpr (kDisplay) {
    encodeRow(r, c[0], w);
    encodeRow(g, c[1], w);
    encodeRow(b, c[2], w);
    r = c[0], g = c[1], b = c[2];
    // Capped at decode's bound (min with it commutes with the max). From the channels directly:
    // in place over a row of channel maxima, the left neighbour's value carried from one pixel
    // to the next kept the loop scalar (a third of buildSlot's time).
    float* m = slot + 9 * w;
    constexpr float kCap = tonemap::kTaaMaxEncoded;
    auto channelMax = [&](int x) { return fmax(fmax(r[x], g[x]), b[x]); };
    if (w == 1) {
      m[0] = fmin(channelMax(0), kCap);
    } else {
      m[0] = fmin(fmax(channelMax(0), channelMax(1)), kCap);
      RTD_IVDEP
      for (int x = 1; x < w - 1; ++x) m[x] = fmin(fmax(fmax(channelMax(x - 1), channelMax(x)), channelMax(x + 1)), kCap);
      m[w - 1] = fmin(fmax(channelMax(w - 2), channelMax(w - 1)), kCap);
    }
  }
  RTD_IVDEP
  for (int x = 0; x < w; ++x) {
    const float R = r[x], G = g[x], B = b[x];  // in place with kDisplay
    c[0][x] = 0.25f * R + 0.5f * G + 0.25f * B;
    c[1][x] = 0.5f * R - 0.5f * B;
    c[2][x] = -0.25f * R + 0.5f * G - 0.25f * B;
  }
  for (int k = 0; k < 3; ++k) {
    const float* in = c[k];
    float *lo = slot + (3 + k) * w, *hi = slot + (6 + k) * w;
    if (w == 1) { lo[0] = hi[0] = in[0]; continue; }
    lo[0] = fmin(in[0], in[1]);
    hi[0] = fmax(in[0], in[1]);
    RTD_IVDEP
    for (int x = 1; x < w - 1; ++x) {
      lo[x] = fmin(fmin(in[x - 1], in[x]), in[x + 1]);
      hi[x] = fmax(fmax(in[x - 1], in[x]), in[x + 1]);
    }
    lo[w - 1] = fmin(in[w - 2], in[w - 1]);
    hi[w - 1] = fmax(in[w - 2], in[w - 1]);
  }
}

#ifdef RTD_SIMD_AVX2
// catmullRomWeights for kLanes fractions.
inline void catmullRomWeightsLanes(vf t, vf w[4]) {
  w[0] = 0.5f * t * ((2.0f - t) * t - 1.0f);
  w[1] = 0.5f * (t * t * (3.0f * t - 5.0f) + 2.0f);
  w[2] = 0.5f * t * ((4.0f - 3.0f * t) * t + 1.0f);
  w[3] = 0.5f * t * t * (t - 1.0f);
  for (int k = 0; k < 4; ++k) w[k] = keepIf(vabs(w[k]) >= 0x1p-24f, w[k]);
}
// The kLanes-pixel twin of catmullRomFetch (8 on avx2, 16 on avx512) for footprints wholly
// inside the frame (the caller checks): the same weights, flushes and summation order, taps as
// vector loads where the footprints are consecutive (locally uniform motion). Otherwise the
// footprints usually still start within 2 kLanes - 4 columns and on two neighbouring rows at
// most (a step in the motion between the lanes, or positions near a texel centre line that
// round to different rows: a third of the groups at 1280x720 in BM_Taa): the taps are then, on
// avx2 where each lane is at most one column and one row off consecutive, selections between
// vector loads (ShiftedFootprints), else permutations of a two-vector window of each row
// (vpermute2), picked per lane between the two rows; gathers only where even that does not hold.
void catmullRomFetchLanes(const Plane3& hist, const float* prevX, const float* prevY, int w, float* out[3]) {
  const vf qx = load(prevX) - 0.5f, qy = load(prevY) - 0.5f;
  const vf fx = vfloor(qx), fy = vfloor(qy);
  vf wx[4], wy[4];
  catmullRomWeightsLanes(qx - fx, wx);
  catmullRomWeightsLanes(qy - fy, wy);
  const vi col = __builtin_convertvector(fx, vi) - 1, top = __builtin_convertvector(fy, vi) - 1;
  const vi base = top * w + col;
  const int first = base[0];
  const bool consecutive = allTrue(base == first + laneIndex());
  if (consecutive) {
    for (int c = 0; c < 3; ++c) prefetchAhead(hist[c].ptr() + first + 3 * size_t(w));
    // The common case (locally uniform motion): the taps are vector loads, the 3 x 4 rows
    // unrolled (rolled, the loop reloaded the row weights per row: BM_Taa 6-8 % slower;
    // docs/performance.md, "Session 13").
    vf sum[3];
#pragma GCC unroll 3
    for (int c = 0; c < 3; ++c) {
      const float* hp = hist[c].ptr() + first;
      sum[c] = splat(0.0f);
#pragma GCC unroll 4
      for (int j = 0; j < 4; ++j) {
        const float* row = hp + size_t(j) * w;
        const vf r = wx[0] * load(row) + wx[1] * load(row + 1) + wx[2] * load(row + 2) + wx[3] * load(row + 3);
        sum[c] += wy[j] * r;
      }
    }
    for (int c = 0; c < 3; ++c) store(out[c], vflush(sum[c]));
    return;
  }
  // Smooth motion on avx2 (passes/shifted_footprints.h): each tap a selection between vector
  // loads, in the same order of sums as above, where the window below costs three operations
  // per tap (BM_Taa 0.95). On avx512 one vpermt2ps per tap does it from fewer loads (the
  // selections there: BM_Taa 1.09).
  if (ShiftedFootprints shifted; kLanes == 8 && shifted.classify(col, top, w, hist[0].size(), 4, 4)) {
    for (int c = 0; c < 3; ++c) {
      const float* hp = hist[c].ptr();
      vf sum = splat(0.0f);
#pragma GCC unroll 4
      for (int j = 0; j < 4; ++j) {
        const vf r = wx[0] * shifted.tap(hp, 0, j, w) + wx[1] * shifted.tap(hp, 1, j, w) + wx[2] * shifted.tap(hp, 2, j, w) +
                     wx[3] * shifted.tap(hp, 3, j, w);
        sum += wy[j] * r;
      }
      store(out[c], vflush(sum));
    }
    return;
  }
  const int colMin = minLane(col), colMax = maxLane(col), topMin = minLane(top), topMax = maxLane(top);
  // The last window row's two vectors end inside the plane (they may run past the row's end).
  const bool windowed = colMax - colMin <= 2 * kLanes - 4 && topMax - topMin <= 1 &&
                        size_t(topMax + 3) * w + colMin + 2 * kLanes <= hist[0].size();
  const vi columns = col - colMin, lower = top != topMin;  // lanes whose footprint starts a row lower
  const int windowRows = 4 + (topMax - topMin);
  for (int c = 0; c < 3; ++c) {
    const float* hp = hist[c].ptr();
    vf lo[5], hi[5];
    for (int j = 0; j < windowRows && windowed; ++j) {
      const float* row = hp + size_t(topMin + j) * w + colMin;
      lo[j] = load(row), hi[j] = load(row + kLanes);
    }
    vf sum = splat(0.0f);
    for (int j = 0; j < 4; ++j) {
      const float* row = hp + size_t(j) * w;
      auto tap = [&](int i) {
        if (!windowed) return vgather(row + i, base);
        const vf upper = vpermute2(lo[j], hi[j], columns + i);
        return windowRows == 4 ? upper : lower ? vpermute2(lo[j + 1], hi[j + 1], columns + i) : upper;
      };
      const vf r = wx[0] * tap(0) + wx[1] * tap(1) + wx[2] * tap(2) + wx[3] * tap(3);
      sum += wy[j] * r;
    }
    store(out[c], vflush(sum));
  }
}

// rows()'s test for catmullRomFetchLanes, for the eight pixels i..i+7 of the frame at once: each
// 4x4 footprint inside the frame, and each pixel `consistent` (Bilinear, every tap of the plain
// bilinear footprint weighted above kTaaNegligibleTap accepted). A record whose footprint was
// slid is left to the scalar test (false here).
bool catmullRomReady8(const Reprojection& rp, size_t i, const float* prevX, const float* prevY, int w, int h) {
  const __m256 qx = _mm256_sub_ps(_mm256_loadu_ps(prevX), _mm256_set1_ps(0.5f));
  const __m256 qy = _mm256_sub_ps(_mm256_loadu_ps(prevY), _mm256_set1_ps(0.5f));
  const __m256 one = _mm256_set1_ps(1.0f);
  const __m256 inside =
      _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(qx, one, _CMP_GE_OQ), _mm256_cmp_ps(qx, _mm256_set1_ps(float(w - 2)), _CMP_LT_OQ)),
                    _mm256_and_ps(_mm256_cmp_ps(qy, one, _CMP_GE_OQ), _mm256_cmp_ps(qy, _mm256_set1_ps(float(h - 2)), _CMP_LT_OQ)));
  if (_mm256_movemask_ps(inside) != 0xff) return false;
  Bilinear8 record, plain;
  if (!record.load(rp, i, false) || !plain.footprint(prevX, prevY, w, h, false)) return false;
  if (_mm256_movemask_epi8(_mm256_cmpeq_epi32(record.base, plain.base)) != -1) return false;
  const __m256 zero = _mm256_setzero_ps(), negligible = _mm256_set1_ps(kTaaNegligibleTap);
  __m256 dropped = zero;  // a tap the plain footprint weighs and the record does not
  for (int t = 0; t < 4; ++t)
    dropped = _mm256_or_ps(dropped, _mm256_andnot_ps(_mm256_cmp_ps(record.weight[t], zero, _CMP_GT_OQ),
                                                     _mm256_cmp_ps(plain.weight[t], negligible, _CMP_GT_OQ)));
  return _mm256_movemask_ps(dropped) == 0;
}
#endif

// The current frame's weight at each pixel of a row (TaaSettings::taaSubpixelAlpha): for a
// history fetched at (px, py) (texel centres at integers), alpha + subpixelAlpha (fx (1 - fx) +
// fy (1 - fy)), at most 1, with fx, fy the fetch's fractional parts; fx (1 - fx) is the
// variance of the bilinear tap weights along x, the blur one resampling adds to the history.
// taa.comp computes the same. t, the distance to the nearest whole number, gives
// t (1 - t) = fx (1 - fx) (symmetric about 1/2); t is bounded to 1/2, so that positions far off
// the frame (vround is exact only below 2^22 on sse2) and NaN or infinite ones (NaN < 1/2 is
// false) still give a weight in [alpha, 1]. Written with the vector helpers: GCC did not
// vectorize the blend loop below with a scalar floor or min in it (TAA 7.7 -> 13.7 ms at
// 1280x720).
void blendWeights(const float* prevX, const float* prevY, int w, float alpha, float subpixelAlpha, float* out) {
  auto lanes = [&](vf px, vf py) {
    const vf tx = vmin(vabs(px - vround(px)), splat(0.5f)), ty = vmin(vabs(py - vround(py)), splat(0.5f));
    return vmin(alpha + subpixelAlpha * (tx * (1.0f - tx) + ty * (1.0f - ty)), splat(1.0f));
  };
  int x = 0;
  for (; x + kLanes <= w; x += kLanes) store(out + x, lanes(load(prevX + x) - 0.5f, load(prevY + x) - 0.5f));
  if (x == w) return;
  float qx[kLanes] = {}, qy[kLanes] = {}, a[kLanes];  // the tail, padded
  for (int k = 0; x + k < w; ++k) qx[k] = prevX[x + k] - 0.5f, qy[k] = prevY[x + k] - 0.5f;
  store(a, lanes(load(qx), load(qy)));
  for (int k = 0; x + k < w; ++k) out[x + k] = a[k];
}

template <bool kDisplay>
void rows(const Reprojection& rp, const Plane3& color, const TaaParams& p, int rowBegin, int rowEnd, const Plane3& hist,
          Plane3& next, Plane3& linearOut, float* window, int slotRow[3], const uint32_t* keys, const RgbExport* output) {
  const float cw = p.crossWeight;
  const int w = color[0].width, h = color[0].height;
  constexpr int kSlotRows = kTaaSlotRows;
  auto slot = [&](int y) {
    float* s = window + size_t(y % 3) * kSlotRows * w;
    if (slotRow[y % 3] != y) { buildSlot<kDisplay>(color, y, w, s); slotRow[y % 3] = y; }
    return s;
  };
  float *hr = window + size_t(kTaaHistoryRow) * w, *hg = hr + w, *hb = hg + w;
  slotRow[0] = slotRow[1] = slotRow[2] = -1;  // colour changes every frame
  for (int y = rowBegin; y != rowEnd; ++y) {
    const float* a = slot(std::max(y - 1, 0));
    const float* c = slot(y);
    const float* b = slot(std::min(y + 1, h - 1));
    // History fetch, bilinear (eight pixels at a time inside) or Catmull-Rom, with
    // clamp-to-edge. A pixel whose reprojected centre lies a pixel or more outside the frame
    // (or, with taaHistoryRejection, whose record accepted no tap) has no history: its
    // "history" is the current colour, which the blend then returns unchanged (with either
    // filter).
    const float *prevX = rp.prevX.row(y), *prevY = rp.prevY.row(y);
    const float *r = color[0].row(y), *g = color[1].row(y), *bl = color[2].row(y);
    // Catmull-Rom only where the reprojection accepted each 2x2 texel that bilinear weighs
    // (above kTaaNegligibleTap; the record Bilinear, its texel kept by its consistency tests,
    // wherever a slide at the border put it in the record's footprint): at a disocclusion or
    // an object's edge the wider 4x4 footprint would carry more of the other surface's history
    // into the pixel than the 2x2 one, so such pixels fall back to bilinear. (Requiring it of
    // the four neighbours too changed the scores by <= 0.02 dB.)
    const size_t row = size_t(y) * w;
    auto consistent = [&](int x, float px, float py) {
      if (rp.kind[row + x] != Reprojection::Bilinear) return false;
      const float fx = std::floor(px), fy = std::floor(py);
      const float ax = px - fx, ay = py - fy;
      const float plain[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
      const int b = rp.base[row + x], bx = b % w, by = b / w;
      for (int t = 0; t < 4; ++t) {
        if (!(plain[t] > kTaaNegligibleTap)) continue;
        const int dx = int(fx) + (t & 1) - bx, dy = int(fy) + (t >> 1) - by;
        if (dx < 0 || dx > 1 || dy < 0 || dy > 1 || !(rp.weights[row + x][dy * 2 + dx] > 0.0f)) return false;
      }
      return true;
    };
    // taaHistoryRejection: the reprojection accepted none of the pixel's history taps.
    auto rejected = [&](int x) { return p.rejection && rp.kind[row + x] == Reprojection::None; };
    auto fetch = [&](int x) {
      const float px = prevX[x] - 0.5f, py = prevY[x] - 0.5f;
      if (!(px > -1.0f && py > -1.0f && px < float(w) && py < float(h)) || rejected(x)) {
        if constexpr (kDisplay) {
          hr[x] = tonemap::taaEncode(r[x]); hg[x] = tonemap::taaEncode(g[x]); hb[x] = tonemap::taaEncode(bl[x]);
        } else {
          hr[x] = r[x]; hg[x] = g[x]; hb[x] = bl[x];
        }
        return;
      }
      if (p.catmullRom && consistent(x, px, py)) {
        float v[3];
        catmullRomFetch(hist, px, py, w, h, v);
        hr[x] = v[0]; hg[x] = v[1]; hb[x] = v[2];
        return;
      }
      const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
      const float ax = px - x0, ay = py - y0;
      const float wt[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
      float v[3] = {0, 0, 0};
      if (x0 >= 0 && y0 >= 0 && x0 < w - 1 && y0 < h - 1) {
        const size_t j = size_t(y0) * w + x0;
        for (int k = 0; k < 3; ++k) {
          const float* hp = hist[k].ptr() + j;
          v[k] = wt[0] * hp[0] + wt[1] * hp[1] + wt[2] * hp[w] + wt[3] * hp[w + 1];
        }
      } else {
        for (int t = 0; t < 4; ++t) {
          const int tx = std::clamp(x0 + (t & 1), 0, w - 1), ty = std::clamp(y0 + (t >> 1), 0, h - 1);
          for (int k = 0; k < 3; ++k) v[k] += wt[t] * hist[k](tx, ty);
        }
      }
      hr[x] = v[0]; hg[x] = v[1]; hb[x] = v[2];
    };
    int x = 0;
#ifdef RTD_SIMD_AVX2
    // Catmull-Rom kLanes pixels at a time where all their 4x4 footprints lie inside the frame
    // and all their history was accepted.
    auto catmullRomReady = [&](int x) {
      for (int k = x; k < x + kLanes; k += 8)
        if (!catmullRomReady8(rp, row + k, prevX + k, prevY + k, w, h)) return false;
      return true;
    };
    for (; x + kLanes <= w && p.catmullRom; x += kLanes) {
      // The positions and the record ahead: read once each, where the history's taps compete
      // for the cache (BM_Taa 0.84-0.91 with encodeRow's; docs/performance.md, "Session 15").
      prefetchAhead(prevX + x), prefetchAhead(prevY + x);
      for (int k = x; k < x + kLanes; k += 8) Bilinear8::prefetchRecord(rp, row + k);
      if (catmullRomReady(x)) {
        float* out[3] = {hr + x, hg + x, hb + x};
        catmullRomFetchLanes(hist, prevX + x, prevY + x, w, out);
      } else {
        for (int k = x; k < x + kLanes; ++k) fetch(k);
      }
    }
    // Bilinear eight pixels at a time where all eight footprints are inside the frame.
    Bilinear8 taps8;
    auto anyRejected8 = [&](int x) {
      for (int k = x; k < x + 8 && p.rejection; ++k)
        if (rp.kind[row + k] == Reprojection::None) return true;
      return false;
    };
    for (; x + 8 <= w && !p.catmullRom; x += 8)
      if (!anyRejected8(x) && taps8.footprint(prevX + x, prevY + x, w, h)) {
        _mm256_storeu_ps(hr + x, taps8.gather(hist[0].ptr()));
        _mm256_storeu_ps(hg + x, taps8.gather(hist[1].ptr()));
        _mm256_storeu_ps(hb + x, taps8.gather(hist[2].ptr()));
      } else {
        for (int k = x; k < x + 8; ++k) fetch(k);
      }
#endif
    for (; x < w; ++x) fetch(x);
    float* blendAlpha = window + size_t(kTaaBlendAlphaRow) * w;
    blendWeights(prevX, prevY, w, p.alpha, p.subpixelAlpha, blendAlpha);
    // Clamp to the 3x3 YCoCg box (moved towards the 5-tap cross's bounds by cw) and blend
    // (vectorized over the row).
    float *n[3] = {next[0].row(y), next[1].row(y), next[2].row(y)};
    // With kDisplay, the decoded output too, in the same loop (tonemap::taaDecode): into the
    // window for an output view, which takes the row from there while it is in cache.
    float* lin[3] = {nullptr, nullptr, nullptr};
    if constexpr (kDisplay)
      for (int k = 0; k < 3; ++k) lin[k] = output ? window + size_t(kTaaOutputRow + k) * w : linearOut[k].row(y);
    // kLanes pixels at a time, written out: GCC's vectorizer left the plain loop scalar on AVX2
    // at the slightest change (a clamp per channel in the decode, the decode from registers),
    // and it read each stored history value back for the decode and divided there.
    // The next history is read again only in the next frame: streamed past the cache where its
    // rows are aligned.
    const bool stream = streamAligned(n[0]) && streamAligned(n[1]) && streamAligned(n[2]);
    // The colour rows that the next row's slot (y + 2) encodes, one line of each plane per
    // group: encodeRow waited on them from memory (BM_Taa 0.92-0.97; docs/performance.md, "Session 18").
    const int ahead = std::min(y + 2, h - 1);
    const float* nextColour[3] = {color[0].row(ahead), color[1].row(ahead), color[2].row(ahead)};
    x = 0;
    for (; x + kLanes <= w; x += kLanes) {
      for (const float* q : nextColour) __builtin_prefetch(q + x);
      const vf hR = load(hr + x), hG = load(hg + x), hB = load(hb + x);
      vf hc[3] = {0.25f * hR + 0.5f * hG + 0.25f * hB, 0.5f * hR - 0.5f * hB, -0.25f * hR + 0.5f * hG - 0.25f * hB};
      for (int k = 0; k < 3; ++k) {
        const vf aMid = load(a + k * w + x), bMid = load(b + k * w + x);
        const vf cLo = load(c + (3 + k) * w + x), cHi = load(c + (6 + k) * w + x);
        const vf boxLo = vmin(vmin(load(a + (3 + k) * w + x), cLo), load(b + (3 + k) * w + x));
        const vf boxHi = vmax(vmax(load(a + (6 + k) * w + x), cHi), load(b + (6 + k) * w + x));
        const vf crossLo = vmin(vmin(aMid, cLo), bMid), crossHi = vmax(vmax(aMid, cHi), bMid);
        const vf lo = boxLo + cw * (crossLo - boxLo), hi = boxHi + cw * (crossHi - boxHi);
        hc[k] = vmin(vmax(hc[k], lo), hi);
      }
      const vf alpha = load(blendAlpha + x), keep = 1.0f - alpha;
      const vf by = alpha * load(c + x) + keep * hc[0];
      const vf bco = alpha * load(c + w + x) + keep * hc[1];
      const vf bcg = alpha * load(c + 2 * w + x) + keep * hc[2];
      vf rgb[3] = {vmax(by + bco - bcg, splat(0.0f)), vmax(by + bcg, splat(0.0f)), vmax(by - bco - bcg, splat(0.0f))};
      if constexpr (kDisplay) {
        const vf top = vmax(vmax(load(a + 9 * w + x), load(c + 9 * w + x)), load(b + 9 * w + x));
        for (int k = 0; k < 3; ++k) rgb[k] = vmin(rgb[k], top);
      }
      for (int k = 0; k < 3; ++k) {
        rgb[k] = vflush(rgb[k]);
        if (stream) streamStore(n[k] + x, rgb[k]);
        else store(n[k] + x, rgb[k]);
        if constexpr (kDisplay) {  // decode(): t / (1 - t), t = y^2, by the reciprocal (vrcp)
          const vf t = rgb[k] * rgb[k];
          store(lin[k] + x, t * vrcp(1.0f - t));
        }
      }
    }
    if (stream) streamFence();
    // One pixel of the loop above, with the bounds lo, hi of its YCoCg history and (kDisplay)
    // the bound `top` of its encoded channels: a YCoCg box corner can lie outside the RGB cube,
    // and bounding the encoded channels by the neighbourhood's largest one keeps the decode
    // within the neighbourhood's range. For the row's tail and the own-surface pixels below.
    auto blendPixel = [&](int x, const float lo[3], const float hi[3], float top) {
      float hc[3] = {0.25f * hr[x] + 0.5f * hg[x] + 0.25f * hb[x], 0.5f * hr[x] - 0.5f * hb[x],
                     -0.25f * hr[x] + 0.5f * hg[x] - 0.25f * hb[x]};
      for (int k = 0; k < 3; ++k) hc[k] = fmin(fmax(hc[k], lo[k]), hi[k]);
      const float alpha = blendAlpha[x];
      const float by = alpha * c[x] + (1 - alpha) * hc[0];
      const float bco = alpha * c[w + x] + (1 - alpha) * hc[1];
      const float bcg = alpha * c[2 * w + x] + (1 - alpha) * hc[2];
      float rgb[3] = {fmax(by + bco - bcg, 0.0f), fmax(by + bcg, 0.0f), fmax(by - bco - bcg, 0.0f)};
      if constexpr (kDisplay)
        for (int k = 0; k < 3; ++k) rgb[k] = fmin(rgb[k], top);
      for (int k = 0; k < 3; ++k) n[k][x] = flushTiny(rgb[k]);  // history: never subnormal (core/flush.h)
      if constexpr (kDisplay)
        for (int k = 0; k < 3; ++k) lin[k][x] = decode(n[k][x]);
    };
    for (; x < w; ++x) {
      float lo[3], hi[3];
      for (int k = 0; k < 3; ++k) {
        const float boxLo = fmin(fmin(a[(3 + k) * w + x], c[(3 + k) * w + x]), b[(3 + k) * w + x]);
        const float boxHi = fmax(fmax(a[(6 + k) * w + x], c[(6 + k) * w + x]), b[(6 + k) * w + x]);
        const float crossLo = fmin(fmin(a[k * w + x], c[(3 + k) * w + x]), b[k * w + x]);
        const float crossHi = fmax(fmax(a[k * w + x], c[(6 + k) * w + x]), b[k * w + x]);
        lo[k] = boxLo + cw * (crossLo - boxLo), hi[k] = boxHi + cw * (crossHi - boxHi);
      }
      blendPixel(x, lo, hi, kDisplay ? fmax(fmax(a[9 * w + x], c[9 * w + x]), b[9 * w + x]) : 0.0f);
    }
    // Own-surface box (TaaSettings::taaOwnSurface): where the 3x3 neighbourhood holds other
    // keys than the pixel's, the pixel is redone with the box (and the cross, and the display
    // bound) over the neighbours of its key only, the pixel itself always in. Not separable,
    // so scalar; the loop above stays the fast path where all nine keys are equal.
    if (keys) {
      const int ya = std::max(y - 1, 0), yb = std::min(y + 1, h - 1);
      const uint32_t* kr[3] = {keys + size_t(ya) * w, keys + size_t(y) * w, keys + size_t(yb) * w};
      const float* slots[3] = {a, c, b};
      const float* src[3][3] = {{color[0].row(ya), color[1].row(ya), color[2].row(ya)}, {r, g, bl},
                                {color[0].row(yb), color[1].row(yb), color[2].row(yb)}};
      // Which pixels have other keys in their 3x3: a column is uniform where its three keys are
      // equal, a pixel's 3x3 where its three columns are and the row's three keys are. Both
      // loops vectorize (the second reads the first's flags from another row: in place, with
      // the left neighbour's flag carried, it ran scalar, ~0.4 ms of a 1280x720 frame at two
      // threads; written with a conditional instead of fmax, GCC's avx512 code for it raised
      // the subnormal flag, Subnormal.SvgfFramesOnExtremeInputs); the flags are floats 0 / 1
      // in the window's rows (float storage that the plane visitors scan).
      float* column = window + size_t(kTaaColumnRow) * w;
      float* mixed = window + size_t(kTaaMixedRow) * w;
      RTD_IVDEP
      for (int x = 0; x < w; ++x) column[x] = float((kr[0][x] != kr[1][x]) | (kr[2][x] != kr[1][x]));
      const uint32_t* k1 = kr[1];
      auto flag = [&](int x) {  // border pixels repeat themselves, as the box does
        const int xl = x > 0 ? x - 1 : 0, xr = x + 1 < w ? x + 1 : x;
        const bool row = k1[xl] != k1[x] || k1[xr] != k1[x];
        return row ? 1.0f : fmax(fmax(column[xl], column[x]), column[xr]);
      };
      mixed[0] = flag(0);
      RTD_IVDEP
      for (int x = 1; x < w - 1; ++x)
        mixed[x] = fmax(float((k1[x - 1] != k1[x]) | (k1[x + 1] != k1[x])), fmax(fmax(column[x - 1], column[x]), column[x + 1]));
      if (w > 1) mixed[w - 1] = flag(w - 1);
      int x = 0;
      for (; x < w; ++x) {
        if (x % kLanes == 0 && x + kLanes <= w && !anyTrue(load(mixed + x) != 0.0f)) {  // 16 (8, 4) at once
          x += kLanes - 1;
          continue;
        }
        if (mixed[x] == 0.0f) continue;
        const uint32_t own = kr[1][x];
        const int xs[3] = {std::max(x - 1, 0), x, std::min(x + 1, w - 1)};
        float boxLo[3], boxHi[3], crossLo[3], crossHi[3];
        for (int k = 0; k < 3; ++k) boxLo[k] = boxHi[k] = crossLo[k] = crossHi[k] = c[k * w + x];
        float top = 0.0f;
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) {
            const int q = xs[i];
            if (kr[j][q] != own && !(j == 1 && i == 1)) continue;
            const bool cross = j == 1 || i == 1;  // the 5-tap cross: the pixel and its 4-neighbours
            for (int k = 0; k < 3; ++k) {
              const float v = slots[j][k * w + q];
              boxLo[k] = fmin(boxLo[k], v);
              boxHi[k] = fmax(boxHi[k], v);
              if (cross) {
                crossLo[k] = fmin(crossLo[k], v);
                crossHi[k] = fmax(crossHi[k], v);
              }
            }
            if constexpr (kDisplay)
              top = fmax(top, fmax(fmax(tonemap::taaEncode(src[j][0][q]), tonemap::taaEncode(src[j][1][q])),
                                   tonemap::taaEncode(src[j][2][q])));
          }
        // The clamp and blend of the loop above, with these bounds.
        float lo[3], hi[3];
        for (int k = 0; k < 3; ++k)
          lo[k] = boxLo[k] + cw * (crossLo[k] - boxLo[k]), hi[k] = boxHi[k] + cw * (crossHi[k] - boxHi[k]);
        blendPixel(x, lo, hi, fmin(top, tonemap::kTaaMaxEncoded));
      }
    }
    if (output) {
      const float* rgb[3] = {kDisplay ? lin[0] : n[0], kDisplay ? lin[1] : n[1], kDisplay ? lin[2] : n[2]};
      output->row(y, rgb);
    }
  }
}
}  // namespace

void taaRows(const Reprojection& rp, const Plane3& color, const TaaParams& p, int rowBegin, int rowEnd, const Plane3& hist,
             Plane3& next, Plane3& linearOut, float* window, int slotRow[3], const uint32_t* keys, const RgbExport* output) {
  if (p.display) rows<true>(rp, color, p, rowBegin, rowEnd, hist, next, linearOut, window, slotRow, keys, output);
  else rows<false>(rp, color, p, rowBegin, rowEnd, hist, next, linearOut, window, slotRow, keys, output);
}

}  // namespace rtd::RTD_SIMD_NS
