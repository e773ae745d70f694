// Temporal accumulation's hot loops (temporal_accumulation_simd.cpp), one copy per CPU path
// (core/simd.h), called by temporal_accumulation.cpp through RTD_SIMD.
#pragma once
#include "core/simd_dispatch.h"
#include "passes/temporal_accumulation.h"

namespace rtd {
/// The planes TemporalAccumulator::accumulateRows reads (previous) and writes (current).
struct AccumulationHistory {
  const Plane3& colorPrev;
  const Plane &m1Prev, &m2Prev, &lengthPrev;
  Plane3& color;
  Plane &m1, &m2, &length;
};
}  // namespace rtd

RTD_SIMD_DECLARE(
void accumulateRows(const Reprojection& rp, const Plane* color, float alpha, float momentsAlpha, int maxHistoryLength,
                    const AccumulationOptions& options, const AccumulationHistory& history, int rowBegin, int rowEnd);
void accumulateRow(const Reprojection& rp, const Plane& length, float alpha, const float* const current[3],
                   const Plane3& history, Plane3& out, int y);
)
