#include "methods/bmfr/qr.h"

#include <algorithm>
#include <cmath>

namespace rtd::bmfr {

namespace {

// Float addition is not associative, so without -ffast-math a plain reduction loop stays
// scalar. Sixteen explicit partial sums let the compiler keep them in two AVX registers, and
// the pairwise final sum also bounds the rounding error over a 1024-row block.
inline float dot(const float* __restrict a, const float* __restrict b, int n) {
  float acc[16] = {};
  int i = 0;
  for (; i + 16 <= n; i += 16)
    for (int l = 0; l < 16; ++l) acc[l] += a[i + l] * b[i + l];
  float tail = 0.0f;
  for (; i < n; ++i) tail += a[i] * b[i];
  for (int w = 8; w >= 1; w /= 2)
    for (int l = 0; l < w; ++l) acc[l] += acc[l + w];
  return acc[0] + tail;
}

// y -= a * x
inline void subtractScaled(float a, const float* __restrict x, float* __restrict y, int n) {
  for (int i = 0; i < n; ++i) y[i] -= a * x[i];
}

}  // namespace

void householderQr(float* cols, int rows, size_t stride, int features, int channels, TriangularSystem& out) {
  out.features = features;
  out.channels = channels;
  const int columns = features + channels;
  for (int k = 0; k < features; ++k) {
    auto store = [&](int j, float v) {
      if (j < features) out.R[k][j] = v;
      else out.r[j - features][k] = v;
    };
    const int n = rows - k;  // rows k.. of every column take part in reflection k
    if (n <= 0) {            // fewer rows than features: nothing left below the diagonal
      for (int j = k; j < columns; ++j) store(j, 0.0f);
      continue;
    }
    float* x = cols + size_t(k) * stride + k;
    const float xk = x[0];
    const float below = dot(x + 1, x + 1, n - 1);
    if (below == 0.0f) {  // already upper triangular in this column (or all zero: R_kk = 0)
      out.R[k][k] = xk;
      for (int j = k + 1; j < columns; ++j) store(j, cols[size_t(j) * stride + k]);
      continue;
    }
    const float norm = std::sqrt(below + xk * xk);
    // H x = alpha e_k with alpha = -sign(x_k) ||x||, so u_k = x_k - alpha adds magnitudes.
    const float alpha = xk >= 0.0f ? -norm : norm;
    const float uk = xk - alpha;
    x[0] = uk;  // column k now holds u (rows k..)
    const float beta = 2.0f / (below + uk * uk);
    for (int j = k + 1; j < columns; ++j) {
      float* y = cols + size_t(j) * stride + k;
      subtractScaled(beta * dot(x, y, n), x, y, n);
      store(j, y[0]);
    }
    out.R[k][k] = alpha;
  }
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

}  // namespace rtd::bmfr
