#include "passes/temporal_accumulation.h"

#include "core/parallel.h"

namespace rtd {

void accumulatePlane(const Reprojection& rp, const Plane& length, float alpha, const Plane& current,
                     const Plane& history, Plane& out) {
  const int w = rp.width;
  parallelRows(rp.height, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const float c = current.data[i];
      if (rp.kind[i] == Reprojection::None) {
        out.data[i] = c;
        continue;
      }
      const float a = newSampleWeight(length.data[i], alpha);
      out.data[i] = a * c + (1.0f - a) * rp.gather(history, i);
    }
  });
}

void TemporalAccumulator::resize(int w, int h) {
  for (int k = 0; k < 2; ++k) {
    rtd::resize(color_[k], w, h);
    m1_[k].resize(w, h);
    m2_[k].resize(w, h);
    length_[k].resize(w, h);
  }
  lum_.resize(w, h);
  lum2_.resize(w, h);
  cur_ = 0;
}

void TemporalAccumulator::reset() {
  // Reprojection with no previous frame marks every pixel None, so stale values are never
  // read; clearing the lengths keeps that true even for a caller that passes old taps.
  for (auto& l : length_) l.fill(0.0f);
}

void TemporalAccumulator::run(const Reprojection& rp, const Plane3& color, float alpha, float momentsAlpha,
                              int maxHistoryLength) {
  run(rp, color, alpha, momentsAlpha, maxHistoryLength, AccumulationOptions{});
}

namespace {
// Plain exponential moving average: w = alpha wherever the pixel has history.
void accumulatePlaneEma(const Reprojection& rp, float alpha, const Plane& current, const Plane& history, Plane& out) {
  const int w = rp.width;
  parallelRows(rp.height, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const float c = current.data[i];
      out.data[i] = rp.kind[i] == Reprojection::None ? c : alpha * c + (1.0f - alpha) * rp.gather(history, i);
    }
  });
}
}  // namespace

void TemporalAccumulator::run(const Reprojection& rp, const Plane3& color, float alpha, float momentsAlpha,
                              int maxHistoryLength, const AccumulationOptions& options) {
  const int prev = cur_;
  cur_ ^= 1;
  updateHistoryLength(rp, length_[prev], maxHistoryLength, length_[cur_]);
  const int w = rp.width;
  parallelRows(rp.height, [&](int y) {
    const float *r = color[0].row(y), *g = color[1].row(y), *b = color[2].row(y);
    float *l = lum_.row(y), *l2 = lum2_.row(y);
    if (options.luminance == MomentLuminance::Rec709) {
      for (int x = 0; x < w; ++x) {
        l[x] = luminance(r[x], g[x], b[x]);
        l2[x] = l[x] * l[x];
      }
    } else {
      for (int x = 0; x < w; ++x) {
        l[x] = momentLuminance(options.luminance, r[x], g[x], b[x]);
        l2[x] = l[x] * l[x];
      }
    }
  });
  for (int c = 0; c < 3; ++c) accumulatePlane(rp, length_[cur_], alpha, color[c], color_[prev][c], color_[cur_][c]);
  if (options.cumulativeMoments) {
    accumulatePlane(rp, length_[cur_], momentsAlpha, lum_, m1_[prev], m1_[cur_]);
    accumulatePlane(rp, length_[cur_], momentsAlpha, lum2_, m2_[prev], m2_[cur_]);
  } else {
    accumulatePlaneEma(rp, momentsAlpha, lum_, m1_[prev], m1_[cur_]);
    accumulatePlaneEma(rp, momentsAlpha, lum2_, m2_[prev], m2_[cur_]);
  }
  if (options.sampleMask) carryUnsampled(rp, *options.sampleMask, prev);
}

void TemporalAccumulator::carryUnsampled(const Reprojection& rp, const Plane& mask, int prev) {
  const int w = rp.width;
  parallelRows(rp.height, [&](int y) {
    const float* m = mask.row(y);
    for (int x = 0; x < w; ++x) {
      if (m[x] != 0.0f) continue;
      const size_t i = size_t(y) * w + x;
      const bool has = rp.kind[i] != Reprojection::None;
      for (int c = 0; c < 3; ++c) color_[cur_][c].data[i] = has ? rp.gather(color_[prev][c], i) : 0.0f;
      m1_[cur_].data[i] = has ? rp.gather(m1_[prev], i) : 0.0f;
      m2_[cur_].data[i] = has ? rp.gather(m2_[prev], i) : 0.0f;
      length_[cur_].data[i] = has ? std::round(rp.gather(length_[prev], i)) : 0.0f;
    }
  });
}

}  // namespace rtd
