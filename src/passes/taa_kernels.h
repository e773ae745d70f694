// TAA's hot loop (taa_simd.cpp), one copy per CPU path (core/simd.h), called by taa.cpp
// through RTD_SIMD.
#pragma once
#include <cmath>

#include "core/simd_dispatch.h"
#include "passes/taa.h"

namespace rtd {
/// Rows of a thread's window slot: Y Co Cg, min Y Co Cg, max Y Co Cg, and (display domain) the
/// horizontal max of the largest encoded channel (Taa::Window).
constexpr int kTaaSlotRows = 10;
/// Catmull-Rom takes a pixel's history only where the reprojection accepted every texel of the
/// plain 2x2 bilinear footprint weighted above this (taa_simd.cpp, `consistent`; taa.comp,
/// `accepted`). A position on a pixel centre line weighs the neighbour line 0, or ~1e-6 after
/// a rounding at another scene scale or camera convention: that texel does not decide between
/// the cubic and bilinear (which differ along the other axis). The cubic's own weights on a
/// line this close are below ~kTaaNegligibleTap / 2, so a rejected texel there brings at most
/// that much of another surface's history.
constexpr float kTaaNegligibleTap = 1.0f / 256.0f;
/// The current frame's weight at a pixel whose history is fetched at (px, py) (texel centres at
/// integers): alpha + subpixelAlpha (fx (1 - fx) + fy (1 - fy)), at most 1, with fx, fy the
/// fetch's fractional parts (TaaSettings::taaSubpixelAlpha). fx (1 - fx) is the variance of the
/// bilinear tap weights along x: the blur one resampling adds to the history. taa.comp's
/// version is the same. Written for the vectorizer (no floor, int conversion or std::min, which
/// keep GCC from vectorizing the blend loop: TAA 7.7 -> 13.7 ms at 1280x720): t, the distance
/// to the nearest whole number (rounded by adding and subtracting 1.5 * 2^23), gives
/// t (1 - t) = fx (1 - fx), as that is symmetric about 1/2; exact for |p| < 2^22, and in
/// [alpha, 1] for any finite p (t is bounded to 1/2 by min(t, 1/2) = (t + 1/2 - |t - 1/2|) / 2),
/// 1 for an infinite or NaN position (the comparison is false).
inline float taaPixelAlpha(float alpha, float subpixelAlpha, float px, float py) {
  constexpr float kRound = 12582912.0f;  // 1.5 * 2^23
  float tx = std::fabs(px - ((px + kRound) - kRound)), ty = std::fabs(py - ((py + kRound) - kRound));
  tx = 0.5f * (tx + 0.5f - std::fabs(tx - 0.5f));
  ty = 0.5f * (ty + 0.5f - std::fabs(ty - 0.5f));
  const float a = alpha + subpixelAlpha * (tx * (1.0f - tx) + ty * (1.0f - ty));
  return a < 1.0f ? a : 1.0f;
}
}  // namespace rtd

RTD_SIMD_DECLARE(
/// Taa::runRows once there is history: `window` holds 3 * kTaaSlotRows + 5 rows of the width
/// (the slots, the fetched history, the own-surface box's flags, the blend weights).
/// `next` receives the clamped blend (the next frame's history); with p.display, `linearOut`
/// receives its taaDecode (otherwise it is unused: `next` is the output). `keys` (or nullptr):
/// the surface keys of the own-surface box (TaaSettings::taaOwnSurface).
void taaRows(const Reprojection& rp, const Plane3& color, const TaaParams& p, int rowBegin, int rowEnd,
             const Plane3& history, Plane3& next, Plane3& linearOut, float* window, int slotRow[3],
             const uint32_t* keys);
)
