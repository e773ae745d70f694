// History footprints of kLanes consecutive pixels under smooth motion, for the *_simd.cpp files
// that read history taps a group of pixels at a time (after core/simd.h; the reprojection's tap
// tests and TAA's Catmull-Rom fetch). Under a camera's motion the footprints of neighbouring
// pixels start at consecutive texels except where the motion field crosses a whole texel between
// two lanes (a one-column step) or the positions straddle a texel row (a one-row step): each
// lane's footprint starts 0 or 1 column right of "first + lane" and 0 or 1 row lower. Every tap
// is then lane k of a vector load at one of four offsets, selected per lane, where a gather
// costs a load per lane (and a two-vector permutation three operations on avx2). 25-30 % of the
// groups of the synthetic scene at 1280x720 have this layout, the rest are consecutive.
#pragma once
#include <cstddef>

#include "core/simd.h"

namespace rtd::RTD_SIMD_NS {

struct ShiftedFootprints {
  size_t first = 0;  ///< index of the texel at row topMin, column shiftMin (lane 0's if unshifted)
  vi right{};        ///< lanes whose footprint starts one column right of first + lane
  vi lower{};        ///< lanes whose footprint starts one row below first's
  bool twoRows = false;

  /// Whether the footprints starting at texels (col, top) of a w-wide plane of planeSize floats
  /// have this layout, with `rows` x `columns` taps each (2 x 2 bilinear, 4 x 4 Catmull-Rom)
  /// whose loads stay inside the plane (they may run past a row's end into the next row).
  /// Tested with vector compares against the first lane: a minimum over the lanes cost more than
  /// the gathers it saves where the motion is noisy (BM_ReprojectJittered 1.3x on avx512).
  bool classify(vi col, vi top, int w, size_t planeSize, int rows, int columns) {
    const vi shift = col - laneIndex();
    const vi ds = shift - shift[0], dt = top - top[0];
    const bool sUp = allTrue((ds == 0) | (ds == 1)), sDown = !sUp && allTrue((ds == 0) | (ds == -1));
    const bool tUp = allTrue((dt == 0) | (dt == 1)), tDown = !tUp && allTrue((dt == 0) | (dt == -1));
    if (!(sUp || sDown) || !(tUp || tDown)) return false;
    const int shiftMin = shift[0] - sDown, topMin = top[0] - tDown;
    twoRows = !allTrue(top == topMin);
    const ptrdiff_t start = ptrdiff_t(topMin) * w + shiftMin;
    // The last load: row rows - 1 (+ 1 lower), column columns - 1 (+ 1 right), kLanes floats.
    if (start < 0 || size_t(start) + size_t(rows - 1 + twoRows) * w + size_t(columns + kLanes) > planeSize) return false;
    first = size_t(start);
    right = shift != shiftMin;
    lower = top != topMin;
    return true;
  }

  /// Tap (dx, dy) of every lane's footprint in plane p (w floats a row).
  vf tap(const float* p, int dx, int dy, int w) const {
    const float* r = p + first + size_t(dy) * w + dx;
    vf v = right ? load(r + 1) : load(r);
    if (twoRows) v = lower ? (right ? load(r + w + 1) : load(r + w)) : v;
    return v;
  }
};

}  // namespace rtd::RTD_SIMD_NS
