// Half floats (IEEE 754 binary16, Format::Half*) on the host: exact conversions, the import of
// a row of half pixels into float planes and the export of RGB planes into a Half3/Half4 view.
// The Vulkan backend reads halves in its import shader and uses these for host outputs.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/plane.h"
#include "core/sanitize.h"
#include "rtd/image.h"

namespace rtd {

/// The float a half's bits stand for (exact: every half is a float), NaN staying NaN.
float halfToFloat(uint16_t h);
/// The half nearest to v (ties to even); beyond the largest half (65504) +-infinity, NaN a
/// quiet NaN. Subnormal halves are produced and read exactly.
uint16_t floatToHalf(float v);

/// n halves (at any address: 2-byte alignment is not required) into floats, and back; F16C
/// instructions on the avx2 and avx512 CPU paths (core/cpu_path.h), the exact scalar
/// conversions above on sse2.
void halvesToFloats(const void* halves, float* dst, size_t n);
void floatsToHalves(const float* src, void* halves, size_t n);

/// One row of w half pixels (`pixelStride` bytes apart, channels packed, any alignment) into
/// the first nc planes' rows `dst`, sanitized into `range` as importFrame() does for floats
/// (sanitizeValue), counted in `bad`.
void importHalfRow(const char* src, size_t pixelStride, int nc, float* const* dst, int w, ValueRange range,
                   SanitizeCounts& bad);

/// Row y of a Half3/Half4 view (RgbExport::row): RGB plus the separated emission rows e (if
/// not null), alpha 1; `packed`: the pixels are 3 or 4 halves apart.
void exportHalfRow(const float* const rgb[3], const float* const* e, const ImageView& out, int y, bool packed);

}  // namespace rtd
