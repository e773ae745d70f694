#include "passes/reprojection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/simd_dispatch.h"

namespace rtd {

const float kFallbackKernel3x3[9] = {0.0778f, 0.1233f, 0.0778f, 0.1233f, 0.1953f,
                                     0.1233f, 0.0778f, 0.1233f, 0.0778f};

void Reprojection::resize(int w, int h) {
  width = w;
  height = h;
  const size_t n = size_t(w) * h;
  kind.assign(n, None);
  base.assign(n, 0);
  weights.assign(n, {0, 0, 0, 0});
  mask3x3.assign(n, 0);
  prevX.resize(w, h);
  prevY.resize(w, h);
}

std::array<size_t, 3> Reprojection::counts() const {
  std::array<size_t, 3> c{0, 0, 0};
  for (uint8_t k : kind) ++c[k];
  return c;
}

int Reprojection::taps(size_t i, Taps& out) const {
  out.count = 0;
  if (kind[i] == Bilinear) {
    const int offsets[4] = {0, 1, width, width + 1};
    for (int t = 0; t < 4; ++t)
      if (weights[i][t] != 0.0f) {
        out.index[out.count] = base[i] + offsets[t];
        out.weight[out.count++] = weights[i][t];
      }
  } else if (kind[i] == Fallback3x3) {
    float wsum = 0.0f;
    for (int t = 0; t < 9; ++t)
      if (mask3x3[i] & (1u << t)) {
        out.index[out.count] = base[i] + (t / 3 - 1) * width + (t % 3 - 1);
        out.weight[out.count++] = kFallbackKernel3x3[t];
        wsum += kFallbackKernel3x3[t];
      }
    for (int t = 0; t < out.count; ++t) out.weight[t] /= wsum;
  }
  return out.count;
}

float Reprojection::gather3x3(const Plane& h, size_t i) const {
  Taps t;
  taps(i, t);
  return t.gather(h);
}

}  // namespace rtd

RTD_SIMD_DECLARE(void reprojectRows(const FrameData& current, const FrameData* previous,
                                    const ReprojectionSettings& s, Reprojection& out, int rowBegin, int rowEnd);)

namespace rtd {
void reprojectRows(const FrameData& cur, const FrameData* previous, const ReprojectionSettings& s, Reprojection& out,
                   int rowBegin, int rowEnd) {
  RTD_SIMD(reprojectRows)(cur, previous, s, out, rowBegin, rowEnd);
}

void reproject(const FrameData& cur, const FrameData* previous, const ReprojectionSettings& s, Reprojection& out,
               const std::function<void(int, int)>& afterRows) {
  if (out.width != cur.width || out.height != cur.height) out.resize(cur.width, cur.height);
  tbb::parallel_for(tbb::blocked_range<int>(0, cur.height, 4), [&](const tbb::blocked_range<int>& rows) {
    reprojectRows(cur, previous, s, out, rows.begin(), rows.end());
    if (afterRows) afterRows(rows.begin(), rows.end());
  });
}

}  // namespace rtd
