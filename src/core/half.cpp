#include "core/half.h"

#include <cstring>
#include <vector>

#include "core/half_kernels.h"

namespace rtd {

float halfToFloat(uint16_t h) {
  const uint32_t sign = uint32_t(h & 0x8000u) << 16, exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
  uint32_t bits;
  if (exponent == 0x1f) {
    bits = sign | 0x7f800000u | (mantissa << 13);  // infinity, NaN (payload kept)
  } else if (exponent != 0) {
    bits = sign | ((exponent + 127 - 15) << 23) | (mantissa << 13);
  } else {
    // Zero or subnormal: mantissa * 2^-24, exact in float.
    const float v = float(mantissa) * 0x1p-24f;
    return sign ? -v : v;
  }
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}

uint16_t floatToHalf(float v) {
  uint32_t f;
  std::memcpy(&f, &v, 4);
  const uint16_t sign = uint16_t((f >> 16) & 0x8000u);
  const uint32_t a = f & 0x7fffffffu;
  if (a > 0x7f800000u) return uint16_t(sign | 0x7e00u | ((a >> 13) & 0x3ffu));  // NaN stays a (quiet) NaN
  if (a >= 0x47800000u) return uint16_t(sign | 0x7c00u);                        // >= 2^16: infinity
  if (a >= 0x38800000u) {
    // Normal half (>= 2^-14): drop 13 mantissa bits, round to nearest even. A carry out of the
    // mantissa moves to the next exponent, and from 65504 on to infinity, as it should.
    uint32_t h = ((a >> 23) - 127 + 15) << 10 | ((a >> 13) & 0x3ffu);
    const uint32_t rest = a & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;
    return uint16_t(sign | h);
  }
  if (a <= 0x33000000u) return sign;  // <= 2^-25: rounds to zero (2^-25 is a tie, to even 0)
  // Subnormal half: round(v * 2^24) = the float's 24-bit mantissa shifted right by 126 - e.
  const uint32_t m = (a & 0x7fffffu) | 0x800000u, shift = 126 - (a >> 23);
  uint32_t h = m >> shift;
  const uint32_t rest = m & ((1u << shift) - 1), halfway = 1u << (shift - 1);
  if (rest > halfway || (rest == halfway && (h & 1u))) ++h;
  return uint16_t(sign | h);
}

void halvesToFloats(const void* halves, float* dst, size_t n) {
  RTD_SIMD(halvesToFloatsBulk)(static_cast<const char*>(halves), dst, n);
}

void floatsToHalves(const float* src, void* halves, size_t n) {
  RTD_SIMD(floatsToHalvesBulk)(src, static_cast<char*>(halves), n);
}

void importHalfRow(const char* src, size_t pixelStride, int nc, float* const* dst, int w, ValueRange range,
                   SanitizeCounts& bad) {
  // The row's halves, from the first pixel's first channel to the last pixel's last one, in one
  // conversion (the pixel stride is a multiple of 2: checked); then each pixel's channels.
  const size_t stride = pixelStride / 2, n = size_t(w - 1) * stride + size_t(nc);
  thread_local std::vector<float> row;
  if (row.size() < n) row.resize(n);
  halvesToFloats(src, row.data(), n);
  for (int x = 0; x < w; ++x)
    for (int c = 0; c < nc; ++c) dst[c][x] = sanitizeValue(row[size_t(x) * stride + c], range, bad);
}

void exportHalfRow(const float* const rgb[3], const float* const* e, const ImageView& out, int y, bool packed) {
  // The row as interleaved floats, then converted to halves in one go.
  const int stride = channelCount(out.format);
  thread_local std::vector<float> row;
  row.resize(size_t(out.width) * stride);
  for (int k = 0; k < 3; ++k)
    for (int x = 0; x < out.width; ++x) row[size_t(x) * stride + k] = e ? rgb[k][x] + e[k][x] : rgb[k][x];
  if (stride == 4)
    for (int x = 0; x < out.width; ++x) row[size_t(x) * 4 + 3] = 1.0f;
  if (packed) {
    floatsToHalves(row.data(), out.pixel<char>(0, y), row.size());
  } else {
    for (int x = 0; x < out.width; ++x) floatsToHalves(row.data() + size_t(x) * stride, out.pixel<char>(x, y), stride);
  }
}

}  // namespace rtd
