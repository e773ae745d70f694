// SVGF-specific passes (Schied et al. 2017 Sec. 4.2 and the variants' changes), exposed for
// the tests. The a-trous filter itself is the shared pass in src/passes/atrous.h.
#pragma once
#include "passes/atrous.h"
#include "rtd/methods/svgf.h"

namespace rtd::svgf {

/// What the variance estimate reads for one radiance stream.
struct VarianceInputs {
  const Plane* historyLength = nullptr;  ///< frames, including the current one
  const Plane* moment1 = nullptr;        ///< accumulated E[l]
  const Plane* moment2 = nullptr;        ///< accumulated E[l^2]
  const Plane3* current = nullptr;       ///< this frame's demodulated sample (spatial estimate from luminance)
  const Plane3* accumulated = nullptr;   ///< accumulated colour: the filter's input
};

struct VarianceParams {
  int shortHistoryFrames = 4;
  SvgfShortHistory shortHistory = SvgfShortHistory::spatialEstimate;
  int radius = 3;                 ///< spatial window (2 radius + 1)^2
  bool fromMoments = false;       ///< Voorhuis: window average of accumulated moments
  float sigmaDepth = 1.0f, depthEpsilon = 1e-2f;
  int normalExponent = 128;
  MomentLuminance luminance = MomentLuminance::Rec709;
};

/// Level-0 input of the filter: out.color = accumulated colour, out.lum its luminance, out.var
/// = max(0, mu2 - mu1^2) where the history length n >= shortHistoryFrames; where it is shorter
/// and the mode is spatialEstimate, the depth/normal-weighted window estimate
/// E_w[l^2] - E_w[l]^2 (l: current luminance, or the accumulated moments). Returns the number
/// of pixels that used the spatial estimate.
size_t estimateVariance(const AtrousGuide& guide, const VarianceInputs& in, const VarianceParams& p, AtrousImage& out);

/// Per-pixel multiplier of sigma_l: 0 where w_l is off (Dundr, short history), Voorhuis Eq. 8
/// where enabled, else 1.
void luminanceSigmaScale(const Plane& historyLength, const SvgfSettings& s, PaddedPlane& out);

/// 3x3 per-channel median (Voorhuis Sec. 6, fireflies) of pixels whose roughness is >= 0.9
/// (diffuse), or of every pixel when `roughness` is null; others are copied.
void median3x3(const Plane3& in, const Plane* roughness, Plane3& out);

/// The executed tap spacings for `iterations` levels in `order`.
void levelSteps(SvgfLevelOrder order, int iterations, int* steps);

}  // namespace rtd::svgf
