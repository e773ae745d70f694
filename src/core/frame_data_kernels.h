// Import's and export's per-row loops (frame_data_simd.cpp), one copy per CPU path
// (core/simd.h), called by frame_data.cpp through RTD_SIMD.
#pragma once
#include <bit>
#include <cstdint>

#include <cfloat>

#include "core/flush.h"
#include "core/sanitize.h"
#include "core/simd_dispatch.h"
#include "rtd/denoiser.h"
#include "rtd/image.h"

namespace rtd {

// A buffer's range for the vector kernels; the rule is sanitizeValue (core/sanitize.h), which
// sanitize8 reproduces on eight lanes, deciding on the bits as it does.
struct Bounds {
  float lo, hi;
  static constexpr uint32_t kMaxBits = std::bit_cast<uint32_t>(FLT_MAX), kTinyBits = std::bit_cast<uint32_t>(kTiny);
  /// The reference for sanitize8.
  float sanitize(float v, SanitizeCounts& bad) const { return sanitizeValue(v, {lo, hi}, bad); }
};


}  // namespace rtd

RTD_SIMD_DECLARE(
/// One row of float pixels (`stride` floats each) into the nc planes' rows, sanitized (counted
/// in `bad`). All channels in one pass over the row.
/// `stream`: write around the caches (non-temporal stores, where the rows are 32-byte aligned),
/// for frames too large to stay in cache until the next pass reads them: it saves reading
/// each destination line before overwriting it (measured on the CI-class VM at 1280x720,
/// 2 threads: import 4.1 -> 3.0 ms).
void importFloatRow(const float* src, int stride, int nc, float* const* dst, int w, Bounds b, bool stream,
                    SanitizeCounts& bad);
/// Row y of `out` (Float3 or Float4, alpha 1) from three planes' rows c (+ emission rows e when
/// not null); `packed`: the view's pixels are tightly packed; `stream`: non-temporal stores.
void exportRow(const float* const c[3], const float* const* e, const ImageView& out, int y, bool packed, bool stream);
)
