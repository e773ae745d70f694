#include "passes/taa.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "passes/taa_kernels.h"

namespace rtd {

void Taa::resize(int w, int h) {
  for (auto& hst : history_) rtd::resize(hst, w, h);
  width_ = w;
  windows_.clear();  // re-sized on first use per thread
  valid_ = false;
}

const Plane3& Taa::run(const Reprojection& rp, const Plane3& color, float alpha) {
  begin(color[0].width, color[0].height);
  tbb::parallel_for(tbb::blocked_range<int>(0, color[0].height, 8), [&](const tbb::blocked_range<int>& range) {
    runRows(rp, color, alpha, range.begin(), range.end());
  });
  return result();
}

void Taa::begin(int w, int h) {
  if (width_ != w || history_[0][0].height != h) resize(w, h);
  cur_ ^= 1;
  first_ = !valid_;
  valid_ = true;
}

void Taa::runRows(const Reprojection& rp, const Plane3& color, float alpha, int rowBegin, int rowEnd) {
  const int w = color[0].width;
  Plane3& next = history_[cur_];
  if (first_) {  // no history yet: the output is the current colour
    for (int c = 0; c < 3; ++c) std::copy(color[c].row(rowBegin), color[c].row(rowBegin) + size_t(rowEnd - rowBegin) * w, next[c].row(rowBegin));
    return;
  }
  Window& win = windows_.local();
  if (win.rows.size() != size_t(3 * kTaaSlotRows + 3) * w) win.rows.assign(size_t(3 * kTaaSlotRows + 3) * w, 0.0f);
  RTD_SIMD(taaRows)(rp, color, alpha, rowBegin, rowEnd, history_[cur_ ^ 1], next, win.rows.data(), win.slotRow);
}

}  // namespace rtd
