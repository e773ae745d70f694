// TAA's hot loop (taa_simd.cpp), one copy per CPU path (core/simd.h), called by taa.cpp
// through RTD_SIMD.
#pragma once
#include "core/simd_dispatch.h"
#include "passes/taa.h"

namespace rtd {
/// Rows of a thread's window slot: Y Co Cg, min Y Co Cg, max Y Co Cg, and (display domain) the
/// horizontal max of the largest encoded channel (Taa::Window).
constexpr int kTaaSlotRows = 10;
}  // namespace rtd

RTD_SIMD_DECLARE(
/// Taa::runRows once there is history: `window` holds 3 * kTaaSlotRows + 3 rows of the width.
/// `next` receives the clamped blend (the next frame's history); with p.display, `linearOut`
/// receives its taaDecode (otherwise it is unused: `next` is the output).
void taaRows(const Reprojection& rp, const Plane3& color, const TaaParams& p, int rowBegin, int rowEnd,
             const Plane3& history, Plane3& next, Plane3& linearOut, float* window, int slotRow[3]);
)
