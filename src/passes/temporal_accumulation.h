// Shared pass: temporal accumulation of demodulated radiance and its luminance moments
// (Schied et al. 2017 Sec. 4.1 / Eq. 1.2-1.3 of Higginson), with the cumulative-then-
// exponential weight w = max(1/n, alpha) of Koskela et al. 2019 Sec. 4.1.
#pragma once
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>

#include "core/flush.h"
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

/// y^(1/3) for a positive normal y (infinity gives infinity), rounded to the nearest float:
/// an estimate from y's bits (its exponent divided by 3, ~5 % off) and two of Halley's steps in
/// double precision, x <- x (x^3 + 2 y) / (2 x^3 + y), each cubing the relative error. glibc's
/// cbrtf (frexpf, scalbnf, within 1 ulp) took ~30 % of Gersthofer's frame, whose moments,
/// weights and variance are of L* (cieLightness) per pixel and per a-trous level.
inline float cubeRoot(float y) {
  const float estimate = std::bit_cast<float>(std::bit_cast<uint32_t>(y) / 3u + 709921077u);
  double x = estimate;
  for (int k = 0; k < 2; ++k) {
    const double x3 = x * x * x;
    x *= (x3 + 2.0 * double(y)) / (2.0 * x3 + double(y));
  }
  return y < std::numeric_limits<float>::infinity() ? float(x) : y;
}

/// CIE 1976 lightness L* of relative luminance y (reference white Y_n = 1; HDR values above 1
/// continue the cube-root branch). Gersthofer Sec. 3.4.1 accumulates moments of L*.
inline float cieLightness(float y) {
  constexpr float kDelta3 = 216.0f / 24389.0f;  // (6/29)^3
  const float f = y > kDelta3 ? cubeRoot(y) : y * (841.0f / 108.0f) + 4.0f / 29.0f;
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

/// (1 - G)^e, the history shrink of A-SVGF (Higginson Sec. 2.3.1); integral exponents up to 64
/// by repeated squaring (the GPU's temporal_accumulation_gradient computes it the same way).
inline float historyShrink(float g, float e) {
  const float b = 1.0f - g;
  if (e == std::floor(e) && e >= 0.0f && e <= 64.0f) {
    float r = 1.0f, d = b;
    for (int k = int(e); k; k >>= 1) {
      if (k & 1) r *= d;
      d *= d;
    }
    return r;
  }
  return std::pow(b, e);
}
/// A-SVGF's adaptive history length N' = min(N (1 - G)^e + 1, cap) (Higginson Sec. 2.3.1;
/// Schied et al. 2018), N the reprojected history length (0 without history).
inline float adaptiveHistoryLength(float n, float g, float e, float cap) {
  return std::min(n * historyShrink(g, e) + 1.0f, cap);
}
/// A-SVGF's new-sample weight alpha = mix(max(1/N', minAlpha), 1, G) (the thesis's
/// mix(1/N', 1, G) with Q2RTX's floor; minAlpha = 0 gives the thesis's formula).
inline float adaptiveAlpha(float nPrime, float g, float minAlpha) {
  const float a = std::max(1.0f / nPrime, minAlpha);
  return a + (1.0f - a) * g;
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
  /// image is never stored unless `current` is set.
  const std::vector<Plane>* albedo = nullptr;
  /// When set (sized like the frame), the colour each pixel blends (demodulated when `albedo`
  /// is set) is also stored here, in the same pass, for a later pass that reads the current
  /// frame (SVGF's variance): the same values demodulate() writes, without a pass of its own.
  Plane3* current = nullptr;
  /// Per-pixel colour blend floor, replacing `alpha` (Voorhuis Sec. 7: 0.2 on diffuse and 0.1
  /// on specular primary hits); the moments keep `momentsAlpha`.
  const Plane* alphaPlane = nullptr;
  /// Neighbourhood clipping (Voorhuis Sec. 4.2.3, passes/neighbourhood_clipping.h): the
  /// reprojected colour history is clamped per channel to [clipLow, clipHigh] before the
  /// blend (a box of -inf..inf leaves it). Both or neither.
  const Plane3* clipLow = nullptr;
  const Plane3* clipHigh = nullptr;
  /// false: the luminance moments are neither read nor written (moment1() and moment2() are
  /// then stale); for methods that do not use them (BMFR).
  bool moments = true;
  /// A-SVGF's adaptive history (Schied et al. 2018; Higginson Sec. 2.3.1): per-stratum temporal
  /// gradient G, a plane of ceil(w / s) x ceil(h / s) texels (s = temporalGradientStride), each
  /// covering s x s pixels, clamped to [0, 1] on use. Where set, the history length is
  /// N' = adaptiveHistoryLength(N, G, historyExponent, maxHistoryLength) (not rounded) and both
  /// weights are adaptiveAlpha(N', G, floor) with run()'s alpha and momentsAlpha as the floors
  /// (cumulativeMoments is then ignored). Not combined with sampleMask.
  const Plane* temporalGradient = nullptr;
  int temporalGradientStride = 3;
  float historyExponent = 10.0f;
  /// Called by TemporalAccumulator::run after each chunk of rows [rowBegin, rowEnd) has been
  /// accumulated, on the thread that accumulated it: a method's own pass over those rows of
  /// the results runs while they are in cache instead of reading them back from memory
  /// (SVGF's variance rows, Filter::varianceRows). Null: none.
  std::function<void(int rowBegin, int rowEnd)> afterRows;
};

/// Owns the history of one radiance stream: accumulated colour (three planes), the first and
/// second raw moments of its luminance, and the history length, double-buffered.
class TemporalAccumulator {
 public:
  /// `moments` false: no moment planes are kept; every run must then set
  /// AccumulationOptions::moments = false (BMFR).
  void resize(int w, int h, bool moments = true);
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
  /// Both halves of the double-buffered history (PlaneVisitor).
  void forEachPlane(const PlaneVisitor& visit) const {
    for (int k = 0; k < 2; ++k) {
      visitPlanes(visit, "accumulated colour", color_[k]);
      visitPlane(visit, "moment 1", m1_[k]);
      visitPlane(visit, "moment 2", m2_[k]);
      visitPlane(visit, "history length", length_[k]);
    }
  }
  /// Variance of luminance from the moments, max(0, mu2 - mu1^2) (SVGF Sec. 4.2).
  float temporalVariance(size_t i) const {
    return flushTiny(std::max(0.0f, m2_[cur_].data[i] - squareOrZero(m1_[cur_].data[i])));
  }

 private:
  void run(const Reprojection& rp, const Plane* color, float alpha, float momentsAlpha, int maxHistoryLength,
           const AccumulationOptions& options);
  Plane3 color_[2];
  Plane m1_[2], m2_[2], length_[2];
  int cur_ = 0;
};

}  // namespace rtd
