#include "passes/taa.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "passes/taa_kernels.h"
#include "passes/tonemap.h"

namespace rtd {

void Taa::resize(int w, int h) {
  for (auto& hst : history_) hst = Plane3{};  // allocated by the first run (none where TAA is off)
  width_ = w;
  height_ = h;
  windows_.clear();  // re-sized on first use per thread
  valid_ = false;
}

const Plane3& Taa::run(const Reprojection& rp, const Plane3& color, const TaaSettings& s,
                       const PixelVector<uint32_t>* keys, const RgbExport* output) {
  begin(color[0].width, color[0].height, s, keys, output);
  // Chunks of 16-32 rows: each starts its window by building the two rows around its first
  // (buildSlot), so chunks of 4-8 rows had built ~1.3 slots per row.
  tbb::parallel_for(tbb::blocked_range<int>(0, color[0].height, 32), [&](const tbb::blocked_range<int>& range) {
    runRows(rp, color, range.begin(), range.end());
  });
  return result();
}

void Taa::begin(int w, int h, const TaaSettings& s, const PixelVector<uint32_t>* keys, const RgbExport* output) {
  if (width_ != w || height_ != h) resize(w, h);
  for (auto& hst : history_) allocateOnce(hst, w, h);
  params_ = TaaParams::of(s);
  keys_ = s.taaOwnSurface && keys && keys->size() == size_t(w) * h ? keys->data() : nullptr;
  output_ = output;
  if (params_.display && !output && (linear_[0].width != w || linear_[0].height != h)) rtd::resize(linear_, w, h);
  cur_ ^= 1;
  first_ = !valid_ || display_ != params_.display;  // a history in the other domain is no history
  display_ = params_.display;
  valid_ = true;
}

void Taa::runRows(const Reprojection& rp, const Plane3& color, int rowBegin, int rowEnd) {
  const int w = color[0].width;
  Plane3& next = history_[cur_];
  if (first_) {  // no history yet: the output is the current colour
    const size_t n = size_t(rowEnd - rowBegin) * w;
    for (int c = 0; c < 3; ++c) {
      const float* in = color[c].row(rowBegin);
      if (!params_.display) {
        std::copy(in, in + n, next[c].row(rowBegin));
        continue;
      }
      if (!output_) std::copy(in, in + n, linear_[c].row(rowBegin));
      float* e = next[c].row(rowBegin);
      for (size_t i = 0; i < n; ++i) e[i] = tonemap::taaEncode(in[i]);
    }
    for (int y = rowBegin; y < rowEnd && output_; ++y) {
      const float* in[3] = {color[0].row(y), color[1].row(y), color[2].row(y)};
      output_->row(y, in);
    }
    return;
  }
  Window& win = windows_.local();
  if (win.rows.size() != size_t(kTaaWindowRows) * w) win.rows.assign(size_t(kTaaWindowRows) * w, 0.0f);
  RTD_SIMD(taaRows)(rp, color, params_, rowBegin, rowEnd, history_[cur_ ^ 1], next, linear_, win.rows.data(), win.slotRow,
                    keys_, output_);
}

}  // namespace rtd
