// Import's and export's per-row loops (frame_data_simd.cpp), one copy per CPU path
// (core/simd.h), called by frame_data.cpp through RTD_SIMD.
#pragma once
#include <bit>
#include <cstdint>

#include "core/flush.h"
#include "core/simd_dispatch.h"
#include "rtd/image.h"

namespace rtd {

// The sanitization bounds of a value: radiance must be finite and non-negative before it can
// reach history (a NaN would stay in the exponential average for ever); features only need
// to be finite (magnitudes up to 3e38). Decided on the bits, so an input value that is
// subnormal is never the operand of a floating-point instruction (core/flush.h).
struct Bounds {
  bool nonNegative;
  static constexpr uint32_t kMaxBits = std::bit_cast<uint32_t>(3.0e38f), kTinyBits = std::bit_cast<uint32_t>(kTiny);
  /// v within the bounds, 0 otherwise (counted in `bad`), and magnitudes below kTiny 0 (not
  /// counted: the hot loops never see a subnormal, core/flush.h): the reference for sanitize8.
  float sanitize(float v, uint64_t& bad) const {
    const uint32_t bits = std::bit_cast<uint32_t>(v), magnitude = bits & 0x7fffffffu;
    // NaN and infinities have magnitude bits above kMaxBits; -0 is not negative.
    if (magnitude > kMaxBits || (nonNegative && bits >> 31 && magnitude != 0)) {
      ++bad;
      return 0.0f;
    }
    return magnitude < kTinyBits ? 0.0f : v;
  }
};

}  // namespace rtd

RTD_SIMD_DECLARE(
/// One row of tightly packed float pixels (`stride` floats each) into the nc planes' rows,
/// sanitized; returns the number of values replaced. All channels in one pass over the row.
/// `stream`: write around the caches (non-temporal stores, where the rows are 32-byte aligned),
/// for frames too large to stay in cache until the next pass reads them: it saves reading
/// each destination line before overwriting it (measured on the CI-class VM at 1280x720,
/// 2 threads: import 4.1 -> 3.0 ms).
uint64_t importFloatRow(const float* src, int stride, int nc, float* const* dst, int w, Bounds b, bool stream);
/// Row y of `out` (Float3 or Float4, alpha 1) from three planes' rows c (+ emission rows e when
/// not null); `packed`: the view's pixels are tightly packed; `stream`: non-temporal stores.
void exportRow(const float* const c[3], const float* const* e, const ImageView& out, int y, bool packed, bool stream);
)
