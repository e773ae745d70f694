// The a-trous filter's hot loops (atrous_simd.cpp), compiled once per CPU path (core/simd.h)
// and called by atrous.cpp through RTD_SIMD.
#pragma once
#include <cstddef>

#include "core/simd_dispatch.h"
#include "passes/atrous.h"

namespace rtd {
/// One tap of a level: offset in floats, kernel weight h(q).
struct AtrousTap {
  ptrdiff_t offset;
  float h;
  float k2;  // |k|^2, k the offset in kernel units (Eq. 6 falloff)
};
}  // namespace rtd

RTD_SIMD_DECLARE(
/// atrousLevel's rows: `taps` point-symmetric (tap k opposite tap count - 1 - k) and in
/// atrousLevel's order, row by row without the centre (the pairs' depth terms take each tap's
/// kernel offset from its index), h0 the centre's kernel weight.
void atrousRows(const AtrousGuide& guide, const AtrousLevel& level, const AtrousImage& in, AtrousImage& out,
                const AtrousTap* taps, int tapCount, float h0);
/// spatialVariance's rows, radius R <= a.pad, normal exponent e >= 1.
void spatialVarianceRows(const AtrousGuide& guide, const PaddedPlane& a, const PaddedPlane& b, const Plane& length,
                         float shortHistory, int R, float sigmaDepth, float depthEpsilon, float depthEpsilonRelative, int e,
                         PaddedPlane& var, const PaddedPlane* objectId);
)
