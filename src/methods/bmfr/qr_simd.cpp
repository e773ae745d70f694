// BMFR's QR and back substitution for one CPU path (core/simd.h); qr.cpp dispatches the
// public functions of qr.h, the BMFR pipeline (bmfr_simd.cpp) calls its own path's copy.
#include <algorithm>
#include <cmath>

#include "methods/bmfr/qr.h"
#include "core/simd.h"

namespace rtd::RTD_SIMD_NS::bmfr {

using rtd::bmfr::kMaxChannels;
using rtd::bmfr::kMaxFeatures;
using rtd::bmfr::TriangularSystem;
namespace thisPath = rtd::RTD_SIMD_NS::bmfr;  // (TriangularSystem's namespace has the dispatching twins)

namespace {

// Eight-wide float vectors (GCC/Clang vector extensions: one AVX register where available, an
// SSE pair otherwise). Float addition is not associative, so the compiler would not vectorize
// these reductions itself without -ffast-math.
typedef float Float8 __attribute__((vector_size(32), aligned(4)));
inline Float8 load(const float* p) { return *reinterpret_cast<const Float8*>(p); }
inline void store(float* p, Float8 v) { *reinterpret_cast<Float8*>(p) = v; }
inline float sum(Float8 v) {
  const float a = (v[0] + v[4]) + (v[2] + v[6]), b = (v[1] + v[5]) + (v[3] + v[7]);
  return a + b;
}

// Four partial sums: one accumulator would make the pass wait on the addition's latency.
inline float sumOfSquares(const float* x, int begin, int end) {
  Float8 acc[4] = {};
  int i = begin;
  for (; i + 32 <= end; i += 32)
    for (int q = 0; q < 4; ++q) {
      const Float8 v = load(x + i + 8 * q);
      acc[q] += v * v;
    }
  for (; i < end; i += 8) {
    const Float8 v = load(x + i);
    acc[0] += v * v;
  }
  return sum((acc[0] + acc[1]) + (acc[2] + acc[3]));
}

// One pass over rows [begin, end): every column y[j] -= scale[j] * u, and, for the next
// reflection, dot[j] += x * y[j] with the already updated next column x (look-ahead: the
// update of reflection k and the dot products of reflection k + 1 share one pass).
template <int Count>
void reflectAndDot(const float* u, const float* x, const float* scale, float* const* y, float* dot, int begin, int end) {
  Float8 acc[Count] = {};
  for (int i = begin; i < end; i += 8) {
    const Float8 uu = load(u + i), xx = load(x + i);
    for (int j = 0; j < Count; ++j) {
      const Float8 v = load(y[j] + i) - scale[j] * uu;
      store(y[j] + i, v);
      acc[j] += xx * v;
    }
  }
  for (int j = 0; j < Count; ++j) dot[j] = sum(acc[j]);
}

// dot[j] = x . y[j] over rows [begin, end) for Count columns in one pass over x.
template <int Count>
void dotsOf(const float* x, float* const* y, float* dot, int begin, int end) {
  Float8 acc[Count] = {};
  for (int i = begin; i < end; i += 8) {
    const Float8 xx = load(x + i);
    for (int q = 0; q < Count; ++q) acc[q] += xx * load(y[q] + i);
  }
  for (int q = 0; q < Count; ++q) dot[q] = sum(acc[q]);
}

// Up to kGroup columns per pass: the accumulators, the broadcast scales and the two shared
// vectors fit in the 16 vector registers.
constexpr int kGroup = 6;

void dots(const float* x, float* const* y, int count, float* dot, int begin, int end) {
  for (int j = 0; j < count; j += kGroup) {
    switch (std::min(kGroup, count - j)) {
      case 1: dotsOf<1>(x, y + j, dot + j, begin, end); break;
      case 2: dotsOf<2>(x, y + j, dot + j, begin, end); break;
      case 3: dotsOf<3>(x, y + j, dot + j, begin, end); break;
      case 4: dotsOf<4>(x, y + j, dot + j, begin, end); break;
      case 5: dotsOf<5>(x, y + j, dot + j, begin, end); break;
      default: dotsOf<6>(x, y + j, dot + j, begin, end); break;
    }
  }
}

}  // namespace

void householderQr(float* cols, int rows, size_t stride, int features, int channels, TriangularSystem& out) {
  out.features = features;
  out.channels = channels;
  const int columns = features + channels;
  // Work on whole vectors: rows are padded with zeros to a multiple of 8 (zero rows change no
  // dot product and are never updated), and reflection k runs from row k rounded down to a
  // multiple of 8, with column k's entries above the diagonal zeroed once they are in R.
  const int padded = (rows + 7) & ~7;
  for (int j = 0; j < columns; ++j) std::fill(cols + size_t(j) * stride + rows, cols + size_t(j) * stride + padded, 0.0f);
  auto column = [&](int j) { return cols + size_t(j) * stride; };
  // dot[j] = x . y_j over rows [k & ~7, padded) for the current column x = column k (its rows
  // above k zeroed), computed by the previous reflection's update pass (or directly).
  float dot[kMaxFeatures + kMaxChannels];
  bool dotsReady = false;
  float maxPivot = 0.0f;  // max |R_jj| so far
  for (int k = 0; k < features; ++k) {
    auto keep = [&](int j, float v) {  // entry (k, j) of [R | r]
      if (j < features) out.R[k][j] = v;
      else out.r[j - features][k] = v;
    };
    if (k >= rows) {  // fewer rows than features: nothing left below the diagonal
      for (int j = k; j < columns; ++j) keep(j, 0.0f);
      continue;
    }
    float* x = column(k);
    const int begin = k & ~7;
    std::fill(x + begin, x + k, 0.0f);  // R[0..k)[k], already stored by earlier reflections
    float* y[kMaxFeatures + kMaxChannels];
    const int later = columns - k - 1;
    for (int q = 0; q < later; ++q) y[q] = column(k + 1 + q);
    if (!dotsReady) dots(x, y, later, dot, begin, padded);
    const float xk = x[k];
    x[k] = 0.0f;
    const float below = sumOfSquares(x, begin, padded);
    // Already upper triangular in this column (or all zero: R_kk = 0), or what is left of it
    // is rounding noise: a norm below 2^-20 of the largest pivot so far, which backSubstitute
    // reports as deficient anyway (1e-5); reflecting it would divide by its square, which can
    // underflow (a column exactly dependent on earlier ones leaves residues of ~1e-20).
    if (below == 0.0f || below + xk * xk <= 0x1p-40f * maxPivot * maxPivot) {
      maxPivot = std::max(maxPivot, std::abs(xk));
      x[k] = xk;
      out.R[k][k] = xk;
      for (int j = k + 1; j < columns; ++j) keep(j, column(j)[k]);
      dotsReady = false;
      continue;
    }
    const float norm = std::sqrt(below + xk * xk);
    maxPivot = std::max(maxPivot, norm);
    // H x = alpha e_k with alpha = -sign(x_k) ||x||, so u_k = x_k - alpha adds magnitudes.
    const float alpha = xk >= 0.0f ? -norm : norm;
    const float uk = xk - alpha;
    x[k] = uk;  // column k now holds u (rows k..)
    const float beta = 2.0f / (below + uk * uk);
    // beta u . y_j, from x . y_j: u differs from x only in row k.
    float scale[kMaxFeatures + kMaxChannels];
    for (int q = 0; q < later; ++q) scale[q] = beta * (dot[q] + (uk - xk) * y[q][k]);
    out.R[k][k] = alpha;
    if (k + 1 < features && k + 1 < rows) {
      // The next column first: it is the next reflection's x, whose dot products with the
      // other columns the remaining update passes accumulate.
      float* next = y[0];
      for (int i = begin; i < padded; i += 8) store(next + i, load(next + i) - scale[0] * load(x + i));
      keep(k + 1, next[k]);
      std::fill(next + begin, next + k + 1, 0.0f);  // rows above k + 1 are in R now
      for (int q = 1; q < later; q += kGroup) {
        const int count = std::min(kGroup, later - q);
        switch (count) {
          case 1: reflectAndDot<1>(x, next, scale + q, y + q, dot + q - 1, begin, padded); break;
          case 2: reflectAndDot<2>(x, next, scale + q, y + q, dot + q - 1, begin, padded); break;
          case 3: reflectAndDot<3>(x, next, scale + q, y + q, dot + q - 1, begin, padded); break;
          case 4: reflectAndDot<4>(x, next, scale + q, y + q, dot + q - 1, begin, padded); break;
          case 5: reflectAndDot<5>(x, next, scale + q, y + q, dot + q - 1, begin, padded); break;
          default: reflectAndDot<6>(x, next, scale + q, y + q, dot + q - 1, begin, padded); break;
        }
        for (int c = 0; c < count; ++c) keep(k + 1 + q + c, y[q + c][k]);
      }
      // The next reflection starts at (k + 1) & ~7 >= begin; the rows in between are zero in
      // its column, so the dot products over [begin, padded) are the ones it needs.
      dotsReady = true;
    } else {
      for (int q = 0; q < later; ++q) {
        for (int i = begin; i < padded; i += 8) store(y[q] + i, load(y[q] + i) - scale[q] * load(x + i));
        keep(k + 1 + q, y[q][k]);
      }
      dotsReady = false;
    }
  }
}

void householderQrTiled(float* tiles, int rows, int tileRows, size_t tileStride, int features, int channels,
                        TriangularSystem& out) {
  const int columns = features + channels;
  const int tileCount = (rows + tileRows - 1) / tileRows;
  if (tileCount <= 1) {
    thisPath::householderQr(tiles, rows, tileStride, features, channels, out);
    return;
  }
  // Stack the tiles' triangles: tile t contributes rows [t * features, (t + 1) * features).
  constexpr int kMaxStacked = 16 * kMaxFeatures;
  const int stackedRows = tileCount * features;
  const size_t stackedStride = size_t(stackedRows + 7) & ~size_t(7);
  float stacked[(kMaxFeatures + kMaxChannels) * ((kMaxStacked + 7) & ~7)];
  if (stackedRows > kMaxStacked) {  // more tiles than the stack holds: fall back to one pass
    thisPath::householderQr(tiles, rows, tileStride, features, channels, out);
    return;
  }
  for (int t = 0; t < tileCount; ++t) {
    TriangularSystem tile;
    const int n = std::min(tileRows, rows - t * tileRows);
    thisPath::householderQr(tiles + size_t(t) * columns * tileStride, n, tileStride, features, channels, tile);
    for (int i = 0; i < features; ++i) {
      const size_t row = size_t(t) * features + i;
      for (int j = 0; j < features; ++j) stacked[size_t(j) * stackedStride + row] = j >= i ? tile.R[i][j] : 0.0f;
      for (int c = 0; c < channels; ++c) stacked[size_t(features + c) * stackedStride + row] = tile.r[c][i];
    }
  }
  thisPath::householderQr(stacked, stackedRows, stackedStride, features, channels, out);
}

int backSubstitute(const TriangularSystem& s, float alpha[kMaxChannels][kMaxFeatures], float relativePivotTolerance) {
  const int m = s.features;
  float maxPivot = 0.0f;
  for (int k = 0; k < m; ++k) maxPivot = std::max(maxPivot, std::abs(s.R[k][k]));
  const float tolerance = relativePivotTolerance * maxPivot;
  int deficient = 0;
  for (int k = 0; k < m; ++k)
    if (!(std::abs(s.R[k][k]) > tolerance)) ++deficient;
  for (int c = 0; c < s.channels; ++c)
    for (int k = m - 1; k >= 0; --k) {
      if (!(std::abs(s.R[k][k]) > tolerance)) {
        alpha[c][k] = 0.0f;
        continue;
      }
      float v = s.r[c][k];
      for (int j = k + 1; j < m; ++j) v -= s.R[k][j] * alpha[c][j];
      alpha[c][k] = v / s.R[k][k];
    }
  return deficient;
}

}  // namespace rtd::RTD_SIMD_NS::bmfr
