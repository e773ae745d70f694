// Shared pass: temporal accumulation of demodulated radiance and its luminance moments
// (Schied et al. 2017 Sec. 4.1 / Eq. 1.2-1.3 of Higginson), with the cumulative-then-
// exponential weight w = max(1/n, alpha) of Koskela et al. 2019 Sec. 4.1.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/frame_data.h"
#include "passes/reprojection.h"

namespace rtd {

/// New-sample weight for history length n (including the new sample).
inline float newSampleWeight(float n, float alpha) { return std::max(1.0f / n, alpha); }

/// out = w * current + (1 - w) * reprojected history per plane, w = newSampleWeight(length,
/// alpha) (out = current where the pixel has no history), for row y of three planes with one
/// tap decode per pixel, the current values given as row pointers: BMFR's phase III
/// accumulation of the fitted colour with phase I's taps and history length, each row
/// accumulated as soon as it is synthesized, while it is in cache.
void accumulateRow(const Reprojection& rp, const Plane& length, float alpha, const float* const current[3],
                   const Plane3& history, Plane3& out, int y);

/// CIE 1976 lightness L* of relative luminance y (reference white Y_n = 1; HDR values above 1
/// continue the cube-root branch). Gersthofer Sec. 3.4.1 accumulates moments of L*.
inline float cieLightness(float y) {
  constexpr float kDelta3 = 216.0f / 24389.0f;  // (6/29)^3
  const float f = y > kDelta3 ? std::cbrt(y) : y * (841.0f / 108.0f) + 4.0f / 29.0f;
  return 116.0f * f - 16.0f;
}

/// Which luminance the moments accumulate (added for the SVGF variants).
enum class MomentLuminance : uint8_t { Rec709, Rec601, CieLightness };

inline float momentLuminance(MomentLuminance m, float r, float g, float b) {
  switch (m) {
    case MomentLuminance::Rec601: return 0.299f * r + 0.587f * g + 0.114f * b;
    case MomentLuminance::CieLightness: return cieLightness(std::max(0.0f, luminance(r, g, b)));
    default: return luminance(r, g, b);
  }
}

/// Options of TemporalAccumulator::run beyond the blend weights.
struct AccumulationOptions {
  MomentLuminance luminance = MomentLuminance::Rec709;
  /// true: moments use w = max(1/n, momentsAlpha) like the colour (exact averages for short
  /// histories, Voorhuis Sec. 6); false: w = momentsAlpha wherever there is history (plain
  /// EMA, Schied et al. 2017).
  bool cumulativeMoments = true;
  /// false: colour and moments blend with exactly alpha (momentsAlpha) wherever the pixel has
  /// history, the current sample alone where it has none (Gersthofer Sec. 3.4.1: "a fixed
  /// aggregation factor of alpha = 0.2" if reprojection succeeded); true: the colour weight is
  /// max(1/n, alpha).
  bool cumulativeColor = true;
  /// Progressive rendering with fewer than one sample per pixel (Dundr Sec. 5): where this
  /// plane (Buffer::SampleMask) is 0 the pixel got no sample, so colour, moments and history
  /// length are the reprojected history unchanged (0 where there is none: still missing).
  const Plane* sampleMask = nullptr;
  /// When set, the colour passed to run() is radiance, demodulated on the fly (divided by
  /// demodulationFactor of these three albedo planes, as demodulate() does) so the demodulated
  /// image is never stored. Methods that need it stored (SVGF's variance) demodulate first.
  const std::vector<Plane>* albedo = nullptr;
  /// false: the luminance moments are neither read nor written (moment1() and moment2() are
  /// then stale); for methods that do not use them (BMFR).
  bool moments = true;
};

/// Owns the history of one radiance stream: accumulated colour (three planes), the first and
/// second raw moments of its luminance, and the history length, double-buffered.
class TemporalAccumulator {
 public:
  void resize(int w, int h);
  void reset();

  /// Accumulates `color` (demodulated) with reprojection `rp`, shared between streams.
  /// Moments use `momentsAlpha`; both use the same history length.
  void run(const Reprojection& rp, const Plane3& color, float alpha, float momentsAlpha, int maxHistoryLength);
  void run(const Reprojection& rp, const Plane3& color, float alpha, float momentsAlpha, int maxHistoryLength,
           const AccumulationOptions& options);
  /// The same with the colour as a frame's buffer (three planes), typically radiance with
  /// options.albedo set.
  void run(const Reprojection& rp, const std::vector<Plane>& color, float alpha, float momentsAlpha,
           int maxHistoryLength, const AccumulationOptions& options);

  /// run() in two steps, for methods that run their passes on bands of rows: advance() once
  /// per frame (the current history becomes the previous one), then accumulateRows() once for
  /// every row, from any thread. `color`: three planes.
  void advance();
  void accumulateRows(const Reprojection& rp, const Plane* color, float alpha, float momentsAlpha,
                      int maxHistoryLength, const AccumulationOptions& options, int rowBegin, int rowEnd);

  const Plane3& color() const { return color_[cur_]; }
  /// Methods that feed a filtered result back as history (SVGF: first a-trous level) write here.
  Plane3& color() { return color_[cur_]; }
  const Plane& moment1() const { return m1_[cur_]; }
  const Plane& moment2() const { return m2_[cur_]; }
  const Plane& historyLength() const { return length_[cur_]; }
  /// Bytes of the history planes (both buffers).
  uint64_t bytes() const {
    uint64_t n = 0;
    for (int k = 0; k < 2; ++k) {
      for (const auto& p : color_[k]) n += p.data.size();
      n += m1_[k].data.size() + m2_[k].data.size() + length_[k].data.size();
    }
    return n * sizeof(float);
  }
  /// Variance of luminance from the moments, max(0, mu2 - mu1^2) (SVGF Sec. 4.2).
  float temporalVariance(size_t i) const {
    const float m1 = m1_[cur_].data[i];
    return std::max(0.0f, m2_[cur_].data[i] - m1 * m1);
  }

 private:
  void run(const Reprojection& rp, const Plane* color, float alpha, float momentsAlpha, int maxHistoryLength,
           const AccumulationOptions& options);
  Plane3 color_[2];
  Plane m1_[2], m2_[2], length_[2];
  int cur_ = 0;
};

}  // namespace rtd
