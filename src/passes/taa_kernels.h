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
/// Taa::runRows once there is history: `window` holds 3 * kTaaSlotRows + 4 rows of the width
/// (the slots, the fetched history, the own-surface box's flags).
/// `next` receives the clamped blend (the next frame's history); with p.display, `linearOut`
/// receives its taaDecode (otherwise it is unused: `next` is the output). `keys` (or nullptr):
/// the surface keys of the own-surface box (TaaSettings::taaOwnSurface).
void taaRows(const Reprojection& rp, const Plane3& color, const TaaParams& p, int rowBegin, int rowEnd,
             const Plane3& history, Plane3& next, Plane3& linearOut, float* window, int slotRow[3],
             const uint32_t* keys);
)
