#include "passes/temporal_accumulation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

#include "passes/demodulation.h"
#include "passes/temporal_accumulation_kernels.h"

namespace rtd {

void TemporalAccumulator::resize(int w, int h, bool moments) {
  for (int k = 0; k < 2; ++k) {
    rtd::resize(color_[k], w, h);
    m1_[k] = moments ? Plane(w, h) : Plane();
    m2_[k] = moments ? Plane(w, h) : Plane();
    length_[k].resize(w, h);
  }
  cur_ = 0;
}

void TemporalAccumulator::advance() { cur_ ^= 1; }

void TemporalAccumulator::reset() {
  // Reprojection with no previous frame marks every pixel None, so stale values are never
  // read; clearing the lengths keeps that true even for a caller that passes old taps.
  for (auto& l : length_) l.fill(0.0f);
}

void TemporalAccumulator::run(const Reprojection& rp, const Plane3& color, float alpha, float momentsAlpha,
                              int maxHistoryLength) {
  run(rp, color, alpha, momentsAlpha, maxHistoryLength, AccumulationOptions{});
}

void TemporalAccumulator::run(const Reprojection& rp, const Plane3& color, float alpha, float momentsAlpha,
                              int maxHistoryLength, const AccumulationOptions& options) {
  run(rp, color.data(), alpha, momentsAlpha, maxHistoryLength, options);
}

void TemporalAccumulator::run(const Reprojection& rp, const std::vector<Plane>& color, float alpha,
                              float momentsAlpha, int maxHistoryLength, const AccumulationOptions& options) {
  run(rp, color.data(), alpha, momentsAlpha, maxHistoryLength, options);
}

void TemporalAccumulator::run(const Reprojection& rp, const Plane* color, float alpha, float momentsAlpha,
                              int maxHistoryLength, const AccumulationOptions& options) {
  advance();
  tbb::parallel_for(tbb::blocked_range<int>(0, rp.height, 4), [&](const tbb::blocked_range<int>& rows) {
    accumulateRows(rp, color, alpha, momentsAlpha, maxHistoryLength, options, rows.begin(), rows.end());
    if (options.afterRows) options.afterRows(rows.begin(), rows.end());
  });
}

void TemporalAccumulator::accumulateRows(const Reprojection& rp, const Plane* color, float alpha, float momentsAlpha,
                                         int maxHistoryLength, const AccumulationOptions& options, int rowBegin,
                                         int rowEnd) {
  if (options.moments && m1_[cur_].size() != length_[cur_].size())
    throw std::logic_error("TemporalAccumulator: moments accumulated into a history resized without them");
  const int prev = cur_ ^ 1;
  const AccumulationHistory h{color_[prev], m1_[prev], m2_[prev], length_[prev],
                              color_[cur_], m1_[cur_], m2_[cur_], length_[cur_]};
  RTD_SIMD(accumulateRows)(rp, color, alpha, momentsAlpha, maxHistoryLength, options, h, rowBegin, rowEnd);
}

void accumulateRow(const Reprojection& rp, const Plane& length, float alpha, const float* const current[3],
                   const Plane3& history, Plane3& out, int y) {
  RTD_SIMD(accumulateRow)(rp, length, alpha, current, history, out, y);
}

}  // namespace rtd
