// A-SVGF's own passes (Schied et al. 2018; Higginson Sec. 2.3.1): the temporal gradient of each
// 3x3 stratum (from the renderer's re-shaded gradient samples, or the history anti-lag estimate
// for inputs without them), its a-trous filter on the 1/3-resolution grid, and the filter's
// normals with the reflected-normal toggle. The temporal accumulation that consumes the
// gradient is the shared pass (AccumulationOptions::temporalGradient); the variance and the
// colour a-trous levels are SVGF's (svgf::Filter). Exposed for the tests.
#pragma once
#include <cmath>
#include <vector>

#include "core/frame_data.h"
#include "methods/svgf/svgf_filter.h"
#include "passes/atrous.h"
#include "passes/reprojection.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/asvgf.h"

namespace rtd::asvgf {

/// The SVGF filter's parameters under A-SVGF's settings (Rec. 709 luminance, the 7x7 spatial
/// estimate for short histories, g3x3 before every level, 5x5 B3 spline, steps 1, 2, 4, ...).
svgf::FilterParams filterParams(const AsvgfSettings& s);
/// Buffers asvgf needs in every frame: SVGF's, plus the gradient samples unless the gradient
/// is estimated from history (so a frame without them is refused, naming the buffer).
std::vector<Buffer> requiredBuffers(const AsvgfSettings& s);
/// Read when present: the depth gradient (filter guide) and reflected normals (the toggle).
std::vector<Buffer> extraBuffers(const AsvgfSettings& s);

/// Side of a stratum in pixels: one gradient sample per 3x3 block (Schied 2018, Q2RTX, thesis).
constexpr int kStratum = 3;
/// Strata across `pixels`.
inline int strata(int pixels) { return (pixels + kStratum - 1) / kStratum; }

/// G = (|L_cur - L_prev| / max(L_prev, L_cur))^2, 0 where both are 0 (Higginson Sec. 2.3.1,
/// after Q2RTX): in [0, 1] for non-negative luminances.
inline float temporalGradient(float previous, float current) {
  const float m = std::max(previous, current);
  if (!(m > 0.0f)) return 0.0f;
  const float r = std::abs(current - previous) / m;
  return r * r;
}

/// The 1/3-resolution gradient and what its a-trous levels need: per stratum the features of
/// the pixel holding its sample (depth, normal and the depth gradient scaled to stratum units,
/// i.e. times 3; the stratum's centre pixel where it has no sample), G in level[k].color[0]
/// and the validity (1 where the stratum has a sample) in valid[k].
struct GradientImage {
  int width = 0, height = 0;  ///< strata
  AtrousGuide guide;
  AtrousImage level[2];
  PaddedPlane valid[2];
  PaddedPlane noLuminanceWeight;  ///< zeros: w_l off in the gradient's levels
  Plane result;                   ///< the filtered G, width x height (AccumulationOptions::temporalGradient)
  int last = 0;                   ///< the level filterGradient finished in

  /// For a frame of w x h pixels; `pad` >= the widest tap offset of the gradient's levels.
  void resize(int w, int h, int pad);
  /// Every plane it keeps (PlaneVisitor).
  void forEachPlane(const PlaneVisitor& visit) const {
    guide.forEachPlane(visit);
    for (const auto& l : level) l.forEachPlane(visit);
    for (const auto& v : valid) v.visit(visit, "gradient valid");
    noLuminanceWeight.visit(visit, "gradient sigma scale");
    visitPlane(visit, "gradient", result);
  }
};

/// Border of the gradient planes for `iterations` levels of the 3x3 kernel.
inline int gradientPad(int iterations) { return iterations > 0 ? 1 << (iterations - 1) : 1; }

/// Per stratum: G = scale * temporalGradient(GradientPrevious, GradientCurrent) at the pixel
/// whose GradientSample is set (the first, in scan order, if an engine set several), valid 1;
/// strata without a sample are invalid with G = 0. Features from `guide` (full resolution).
/// Returns the number of strata with a sample.
size_t gradientFromSamples(const Plane& sampleMask, const Plane& previous, const Plane& current,
                           const AtrousGuide& guide, float scale, GradientImage& out);

/// NOT A-SVGF, for inputs without gradient samples (AsvgfGradientSource::historyAntilag), level 0
/// of its estimate: per stratum, over its pixels with history (reprojection `rp`), the mean
/// current luminance Lc (of `current`, demodulated) in colour 0, the mean reprojected history
/// luminance Lh (last frame's `moment1`) in colour 1 and the variance of Lc's mean, V / n with V
/// the pixels' mean temporal variance (last frame's moments), in var; strata without history
/// are invalid. Features from the stratum's centre pixel. The gradient's a-trous levels then
/// average all three over each surface (propagating the variance) and
/// historyAntilagGradient() turns them into G.
size_t historyLuminances(const Reprojection& rp, const Plane3& current, const Plane& moment1, const Plane& moment2,
                         MomentLuminance luminance, const AtrousGuide& guide, GradientImage& out);

/// The estimate's G = scale * (max(0, |Lc - Lh| - k sqrt(V)) / max(Lc, Lh))^2 (0 where both are
/// 0): only the change beyond k standard deviations of the filtered current mean counts.
inline float antilagGradient(float lc, float lh, float variance, float k, float scale) {
  const float m = std::max(lc, lh);
  if (!(m > 0.0f)) return 0.0f;
  const float d = std::max(0.0f, std::abs(lc - lh) - k * std::sqrt(std::max(0.0f, variance)));
  return scale * (d / m) * (d / m);
}

/// `iterations` a-trous levels over the strata (shared atrousLevel, 3x3 binomial kernel, steps
/// 1, 2, 4, ...; w = w_z w_n on the strata features, no luminance weight; invalid strata weigh
/// 0 and are filled from valid neighbours; the variance propagated when `propagateVariance`),
/// then out.result = colour 0 of the last level (G; 0 where nothing valid is within reach).
/// The weights' sigma_z, eps and sigma_n are `v`'s.
void filterGradient(GradientImage& g, int iterations, const svgf::VarianceParams& v, bool propagateVariance = false);

/// After filterGradient on historyLuminances: g.result = antilagGradient of the filtered level.
void historyAntilagGradient(GradientImage& g, float noiseSigmas, float scale);

/// The normal the filter uses (thesis Sec. 1.2.1, Fig. 3.6): Buffer::ReflectedNormal where it is
/// non-zero (mirror pixels) when `reflected` is not null, else Buffer::Normal.
void guideNormals(const std::vector<Plane>& normal, const std::vector<Plane>* reflected, std::vector<Plane>& out);

}  // namespace rtd::asvgf
