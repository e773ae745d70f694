// The RAE's colour transform (rae_codec_kernels.h) for one CPU path (core/simd.h): log1p and
// expm1 on kLanes floats at a time, from a split of the argument into exponent and mantissa
// and minimax polynomials (the coefficients of Moshier's Cephes logf / expf), then a scalar
// tail. These were the encode/decode passes' cost: scalar log1pf / expm1f, three per pixel.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "methods/rae/rae_codec_kernels.h"
#include "core/simd.h"

namespace rtd::RTD_SIMD_NS {

namespace {

constexpr float kLn2Hi = 0.693359375f, kLn2Lo = -2.12194440e-4f;  // ln 2 = hi + lo, hi exact in 9 bits

/// log(u) for u >= 1 (finite): u = 2^e m with m in [sqrt(1/2), sqrt(2)), log(1 + f) of
/// f = m - 1 by its series' minimax form f - f^2/2 + f^3 P(f).
inline vf vlogAtLeastOne(vf u) {
  const vi bits = asInt(u);
  vi e = ((bits >> 23) & 0xff) - 126;
  vf m = asFloat((bits & 0x007fffff) | 0x3f000000);  // [1/2, 1)
  const vi small = m < 0.70710678f;                     // m < sqrt(1/2): use 2m, e - 1
  e += small;                                           // (true lanes are -1)
  m = m + keepIf(small, m);
  const vf f = m - 1.0f;
  const vf z = f * f;
  vf p = splat(7.0376836292e-2f);
  p = p * f - 1.1514610310e-1f;
  p = p * f + 1.1676998740e-1f;
  p = p * f - 1.2420140846e-1f;
  p = p * f + 1.4249322787e-1f;
  p = p * f - 1.6668057665e-1f;
  p = p * f + 2.0000714765e-1f;
  p = p * f - 2.4999993993e-1f;
  p = p * f + 3.3333331174e-1f;
  vf ef;
  for (int k = 0; k < kLanes; ++k) ef[k] = float(e[k]);
  vf y = p * f * z + ef * kLn2Lo - 0.5f * z;
  return f + y + ef * kLn2Hi;
}

/// log1p(x) for x >= 0: log(u) of u = 1 + x (rounded), corrected by the rounding's (x - (u - 1)) / u.
inline vf vlog1p(vf x) {
  const vf u = 1.0f + x;
  return vlogAtLeastOne(u) + (x - (u - 1.0f)) / u;
}

/// expm1(y) for 0 <= y <= 80: y = n ln 2 + r, |r| <= ln2 / 2, e^r - 1 = r + r^2 P(r), then
/// 2^n (e^r - 1) + (2^n - 1), exact for n = 0 where y is small.
inline vf vexpm1(vf y) {
  const vf n = vround(y * 1.44269504088896341f);
  const vf r = (y - n * kLn2Hi) - n * kLn2Lo;
  vf p = splat(1.9875691500e-4f);
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  const vf em1 = r + r * r * p;
  vi ni;
  for (int k = 0; k < kLanes; ++k) ni[k] = int32_t(n[k]);
  const vf scale = asFloat((ni + 127) << 23);  // 2^n
  return scale * em1 + (scale - 1.0f);
}

}  // namespace

void raeLog1pRatio(const float* c, const float* k, float* out, int n) {
  int i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    vf x = vmax(load(c + i), splat(0.0f));
    if (k) x = x / load(k + i);
    x = vmin(x, splat(1e37f));  // keeps 1 + x and the correction finite (log1p(1e37) = 85.2)
    store(out + i, vlog1p(x));
  }
  for (; i < n; ++i) out[i] = std::log1p(std::max(c[i], 0.0f) / (k ? k[i] : 1.0f));
}

void raeExpm1Scaled(const float* y, const float* k, float* out, int n, float yMax) {
  int i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    const vf v = vexpm1(vmin(vmax(load(y + i), splat(0.0f)), splat(yMax)));
    store(out + i, k ? v * load(k + i) : v);
  }
  for (; i < n; ++i) out[i] = std::expm1(std::clamp(y[i], 0.0f, yMax)) * (k ? k[i] : 1.0f);
}

}  // namespace rtd::RTD_SIMD_NS
