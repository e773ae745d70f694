// TAA's hot loop (taa_simd.cpp), one copy per CPU path (core/simd.h), called by taa.cpp
// through RTD_SIMD.
#pragma once
#include "core/simd_dispatch.h"
#include "passes/taa.h"

namespace rtd {
/// Rows of a thread's window slot: Y Co Cg, min Y Co Cg, max Y Co Cg, and (display domain) the
/// horizontal max of the largest encoded channel (Taa::Window).
constexpr int kTaaSlotRows = 10;
/// The rows of a thread's window after its three slots (each the frame's width): the fetched
/// history (three), the own-surface box's mixed-key flags and its column flags, the blend
/// weights, the decoded output row handed to an output view (three); kTaaWindowRows in all.
enum TaaWindowRow : int {
  kTaaHistoryRow = 3 * kTaaSlotRows,
  kTaaMixedRow = kTaaHistoryRow + 3,
  kTaaBlendAlphaRow,
  kTaaColumnRow,
  kTaaOutputRow,
  kTaaWindowRows = kTaaOutputRow + 3
};
/// Catmull-Rom takes a pixel's history only where the reprojection accepted every texel of the
/// plain 2x2 bilinear footprint weighted above this (taa_simd.cpp, `consistent`; taa.comp,
/// `accepted`). A position on a pixel centre line weighs the neighbour line 0, or ~1e-6 after
/// a rounding at another scene scale or camera convention: that texel does not decide between
/// the cubic and bilinear (which differ along the other axis). The cubic's own weights on a
/// line this close are below ~kTaaNegligibleTap / 2, so a rejected texel there brings at most
/// that much of another surface's history.
constexpr float kTaaNegligibleTap = 1.0f / 256.0f;
}  // namespace rtd

RTD_SIMD_DECLARE(
/// Taa::runRows once there is history: `window` holds kTaaWindowRows rows of the width
/// (TaaWindowRow).
/// `next` receives the clamped blend (the next frame's history); with p.display, `linearOut`
/// receives its taaDecode (otherwise it is unused: `next` is the output). `keys` (or nullptr):
/// the surface keys of the own-surface box (TaaSettings::taaOwnSurface). `output` (or
/// nullptr): receives each output row once it is final; `linearOut` is then unused.
void taaRows(const Reprojection& rp, const Plane3& color, const TaaParams& p, int rowBegin, int rowEnd,
             const Plane3& history, Plane3& next, Plane3& linearOut, float* window, int slotRow[3],
             const uint32_t* keys, const RgbExport* output);
)
