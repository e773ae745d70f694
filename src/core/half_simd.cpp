// Bulk half <-> float conversions (core/half.h) for one CPU path (core/simd.h): F16C on the
// avx2 and avx512 paths (both include it), the exact scalar conversions on sse2.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/half.h"
#include "core/half_kernels.h"
#include "core/simd.h"

namespace rtd::RTD_SIMD_NS {

void halvesToFloatsBulk(const char* src, float* dst, size_t n) {
  size_t i = 0;
#ifdef RTD_SIMD_AVX2
  for (; i + 8 <= n; i += 8)
    _mm256_storeu_ps(dst + i, _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(src + 2 * i))));
#endif
  for (; i < n; ++i) {
    uint16_t h;
    std::memcpy(&h, src + 2 * i, 2);
    dst[i] = halfToFloat(h);
  }
}

void floatsToHalvesBulk(const float* src, char* dst, size_t n) {
  size_t i = 0;
#ifdef RTD_SIMD_AVX2
  for (; i + 8 <= n; i += 8)
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + 2 * i),
                     _mm256_cvtps_ph(_mm256_loadu_ps(src + i), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
#endif
  for (; i < n; ++i) {
    const uint16_t h = floatToHalf(src[i]);
    std::memcpy(dst + 2 * i, &h, 2);
  }
}

}  // namespace rtd::RTD_SIMD_NS
