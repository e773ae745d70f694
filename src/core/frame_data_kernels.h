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

/// What import does to a row of float pixels besides sanitizing it, fused into the same pass so
/// that the planes are not read back from memory for it (importFrame).
struct RowFixes {
  /// Buffer::Emission's rows (already imported), subtracted from the nc channels and the result
  /// clamped at 0 (the renderer counts primary-hit emission in Color, Direct and Diffuse), or null.
  const float* const* emission = nullptr;
  /// A unit-vector buffer (nc == 3): report whether some pixel of the row may need renormalizing.
  bool unitVectors = false;
};

/// The test that tells importFloatRow's caller to run renormalizeRow on a row: looser than
/// renormalize's own (half its tolerance), so a pixel renormalize would change is never missed
/// whatever the rounding of the squared length; renormalize then decides pixel by pixel.
constexpr float kUnitCheckTolerance = 0.5f * kUnitLengthTolerance;


}  // namespace rtd

RTD_SIMD_DECLARE(
/// One row of float pixels (`stride` floats each) into the nc planes' rows, sanitized (counted
/// in `bad`), with `fixes` applied on the way. All channels in one pass over the row. Returns,
/// with fixes.unitVectors, whether a pixel's squared length is farther than
/// kUnitCheckTolerance from 1 and not 0 (squares below kTiny count as 0); false otherwise.
/// `stream`: write around the caches (non-temporal stores, where the rows are 32-byte aligned),
/// for frames too large to stay in cache until the next pass reads them: it saves reading
/// each destination line before overwriting it (measured on the CI-class VM at 1280x720,
/// 2 threads: import 4.1 -> 3.0 ms).
bool importFloatRow(const float* src, int stride, int nc, float* const* dst, int w, Bounds b, bool stream,
                    const RowFixes& fixes, SanitizeCounts& bad);
/// Row y of `out` (Float3 or Float4, alpha 1) from three planes' rows c (+ emission rows e when
/// not null); `packed`: the view's pixels are tightly packed; `stream`: non-temporal stores.
void exportRow(const float* const c[3], const float* const* e, const ImageView& out, int y, bool packed, bool stream);
)
