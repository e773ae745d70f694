// Shared pass: the edge-avoiding a-trous wavelet filter (Dammertz et al. 2010) with SVGF's
// edge-stopping weights and variance propagation (Schied et al. 2017 Sec. 4.3, Eq. 3-5).
// SVGF, A-SVGF and any other method that needs it use this one implementation.
//
// Layout (shared/notes/cpu-performance.md): every signal and feature is a float plane with a
// zero border wide enough for the largest tap offset, so the inner loop has no bounds checks;
// eight pixels are filtered at once with all taps accumulated in registers. A border pixel has
// normal (0,0,0), so its normal weight, and hence its whole weight, is 0.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/flush.h"
#include "core/plane.h"
#include "passes/temporal_accumulation.h"

namespace rtd {

/// A plane with a zero border of `pad` pixels on every side (and slack after the last row),
/// rows `stride` floats apart; pad and stride are multiples of kAlignment (the widest vector,
/// one 64-byte line), and stride is an odd count of lines: an a-trous tap window's rows, 2^k
/// rows apart, then fall into different sets of a 4 KiB-periodic L1 (64 sets), where with 1280
/// px (1344 floats, 84 lines) the five rows of the step-16 level all shared the same sets and
/// the 11 planes' windows overflowed its 12 ways (BM_AtrousLevel: step 16 took 1.4x step 1's
/// time, 0.78-0.82 of it with the odd stride; docs/performance.md, "Session 21").
struct PaddedPlane {
  static constexpr int kAlignment = 16;
  int width = 0, height = 0, pad = 0, stride = 0;
  PixelVector<float> data;

  void resize(int w, int h, int padding);
  /// Zeroes everything, border included.
  void clear() { std::fill(data.begin(), data.end(), 0.0f); }
  size_t index(int x, int y) const { return size_t(y + pad) * stride + size_t(x + pad); }
  float* row(int y) { return data.data() + index(0, y); }
  const float* row(int y) const { return data.data() + index(0, y); }
  float& at(int x, int y) { return data[index(x, y)]; }
  float at(int x, int y) const { return data[index(x, y)]; }
  bool sameGeometry(const PaddedPlane& o) const {
    return width == o.width && height == o.height && pad == o.pad && stride == o.stride;
  }
  void copyFrom(const Plane& p);
  void copyTo(Plane& p) const;
  void visit(const PlaneVisitor& v, std::string_view name) const { v(name, data.data(), data.size()); }
};
/// Allocates p (zeros) where it is empty, for planes a pass allocates on first use (core/plane.h's
/// allocateOnce for Plane3).
inline void allocateOnce(PaddedPlane& p, int w, int h, int padding) {
  if (p.data.empty()) p.resize(w, h, padding);
}

// ---- Edge-stopping weights (Schied et al. 2017 Eq. 3), reference scalar forms ----
// Each is exactly 0 where it would fall below 2^kMinWeightExp2 (core/flush.h: never a
// subnormal), as the vectorized filter's weights are.

/// w_z = exp(-|z(p) - z(q)| / (sigma_z |grad z(p) . (p - q)| + eps)).
/// eps = depthEpsilon + depthEpsilonRelative |z(p)| (depthEpsilonAt): the relative part makes
/// w_z independent of the scene's units (issue 12), the absolute one is the original form.
inline float depthWeight(float zp, float zq, float gradDotOffset, float sigmaDepth, float eps) {
  return weightExp(std::abs(zp - zq) / (std::min(sigmaDepth * std::abs(gradDotOffset), kMaxDepthDenominator) + eps));
}
/// eps of w_z at a pixel of depth z.
inline float depthEpsilonAt(float z, float absolute, float relative) { return absolute + relative * std::abs(z); }
/// w_n = max(0, n(p) . n(q))^sigma_n.
inline float normalWeight(float cosine, int exponent) {
  if (!(cosine > 0.0f)) return 0.0f;
  return std::log2(cosine) * float(exponent) < float(kMinWeightExp2) ? 0.0f : std::pow(cosine, float(exponent));
}
/// w_l = exp(-|l(p) - l(q)| / (sigma_l * scale + eps)), scale = sqrt(g3x3(Var)) in SVGF
/// (Dundr Sec. 4.4.3 uses the variance itself).
inline float luminanceWeight(float lp, float lq, float sigmaLuminance, float scale, float eps) {
  return weightExp(std::abs(lp - lq) / (sigmaLuminance * scale + eps));
}
/// Voorhuis Eq. 8: multiplier of sigma_l for h successful reprojections, 8 - min(7, h).
inline float shortHistoryBandwidthScale(int h) { return float(8 - std::min(7, std::max(0, h))); }

/// 1D a-trous kernels: B3 spline (1/16, 1/4, 3/8, 1/4, 1/16) and binomial (1/4, 1/2, 1/4); the
/// 2D kernel is their outer product.
enum class AtrousKernel { B3Spline5x5, Binomial3x3 };
inline int kernelRadius(AtrousKernel k) { return k == AtrousKernel::B3Spline5x5 ? 2 : 1; }
inline float kernelWeight1D(AtrousKernel k, int d) {
  static const float b3[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
  static const float bi[3] = {0.25f, 0.5f, 0.25f};
  return k == AtrousKernel::B3Spline5x5 ? b3[d + 2] : bi[d + 1];
}

/// Per-pixel guide features of the filter, with borders.
struct AtrousGuide {
  PaddedPlane depth, normal[3], gradX, gradY;

  void resize(int w, int h, int pad);
  /// Copies depth and normals; the screen-space depth gradient comes from `depthGradient`
  /// (Buffer::DepthGradient) when given, else from the smaller one-sided difference per axis
  /// (so a silhouette next to a pixel does not widen its depth tolerance). Where
  /// |grad z| > maxDepthSlope * z (maxDepthSlope > 0) the gradient is made huge, which turns
  /// the depth weight off there (Dundr Sec. 4.4.2).
  void build(const Plane& depthPlane, const std::vector<Plane>& normalPlanes, const std::vector<Plane>* depthGradient,
             float maxDepthSlope);
  /// build() for rows [rowBegin, rowEnd) only, on the calling thread (a method builds them
  /// right after another pass over the same rows of the frame, e.g. reprojectRows).
  void buildRows(const Plane& depthPlane, const std::vector<Plane>& normalPlanes,
                 const std::vector<Plane>* depthGradient, float maxDepthSlope, int rowBegin, int rowEnd);
  void forEachPlane(const PlaneVisitor& v) const {
    for (const PaddedPlane* p : {&depth, &normal[0], &normal[1], &normal[2], &gradX, &gradY}) p->visit(v, "guide");
  }
};

/// The filtered signal: colour, the luminance used by w_l, and the luminance variance.
struct AtrousImage {
  PaddedPlane color[3], lum, var;
  void resize(int w, int h, int pad);
  void forEachPlane(const PlaneVisitor& v) const {
    for (const PaddedPlane* p : {&color[0], &color[1], &color[2], &lum, &var}) p->visit(v, "a-trous image");
  }
};

/// Parameters of one a-trous level.
struct AtrousLevel {
  AtrousKernel kernel = AtrousKernel::B3Spline5x5;
  int step = 1;                ///< tap spacing 2^i
  float sigmaDepth = 1.0f;
  /// eps of w_z at p: depthEpsilon + depthEpsilonRelative |z(p)| (depthEpsilonAt); their sum
  /// must be > 0 wherever z(p) is a surface.
  float depthEpsilon = 1e-2f;
  float depthEpsilonRelative = 0.0f;
  int normalExponent = 128;    ///< >= 1
  /// Luminance weight bandwidth at the centre pixel p: sigma_l * k(p) * s(p) + eps, with
  /// s = sqrt(V) (Schied) or V (varianceScale, Dundr), V = g3x3(var) if prefilterVariance
  /// (Schied Eq. 5; computed here, not as a separate pass) else var, and k(p) from `sigmaScale`
  /// (1 when null; 0 switches w_l off at p).
  float sigmaLuminance = 4.0f;
  float luminanceEpsilon = 1e-10f;
  bool prefilterVariance = true;
  bool varianceScale = false;
  const PaddedPlane* sigmaScale = nullptr;
  /// Var' = sum h^2 w^2 Var / (sum h w)^2 (Schied Eq. 4); otherwise out.var is left untouched.
  bool propagateVariance = true;
  /// Luminance written to out.lum for the next level's w_l.
  MomentLuminance luminance = MomentLuminance::Rec709;
  /// Sparse input (Dundr Sec. 5): pixels where `validIn` is 0 carry no data and weigh 0, the
  /// centre included; a pixel that receives any weight becomes valid in `validOut` (so the
  /// levels fill holes), one with none stays 0 with colour 0. Both null: dense.
  const PaddedPlane* validIn = nullptr;
  PaddedPlane* validOut = nullptr;
  /// Gersthofer's glossy weights (Eq. 3.2), both null for none:
  /// w_zi = exp(-|z_i(p) - z_i(q)| k_zi(p) / (sqrt(g3x3(Var)(p)) + eps_l)) with z_i =
  /// `indirectDistance` (the accumulated indirect ray length) and k_zi = `indirectDistanceScale`
  /// (1 - roughness(p), 0 where the weight is off). w_r is a per-pixel factor on every
  /// neighbour tap, which under the normalization equals dividing the centre weight by it:
  /// `centreScale` holds 1/w_r(p) (1 where w_r is off); may be null alone.
  const PaddedPlane* indirectDistance = nullptr;
  const PaddedPlane* indirectDistanceScale = nullptr;
  const PaddedPlane* centreScale = nullptr;
  /// Voorhuis Eq. 6 (glossy pixels): where this plane holds c(p) > 0, every tap's weight is
  /// multiplied by exp(-c(p) |k|^2), k the tap's offset in kernel units (-2..2 per axis, not
  /// pixels). glossySpatialFalloff() turns Eq. 6's sigma_spatial into c. Null: off.
  const PaddedPlane* spatialFalloff = nullptr;
  /// Per-pixel keys (small integers stored as floats), or null: a tap whose key differs from
  /// the centre's weighs 0, in either direction. The reflected guide (Voorhuis Sec. 4.1) keys
  /// its mirror pixels apart: their depth and normal are the virtual image's, which compare
  /// with other mirror pixels' but not with the own features of the surface around the mirror.
  const PaddedPlane* surfaceKey = nullptr;
  /// The last level of a stream that is the method's whole output (SVGF's sum and
  /// remodulation, Schied Sec. 4, fused into the level that produces it): where set, the
  /// filtered colour times demodulationFactor(remodulateAlbedo[c]) (the colour itself where
  /// `remodulateAlbedo` is null) goes to these unpadded planes of the frame's size instead of
  /// out.color, and no luminance is written (no level reads it). Only with propagateVariance
  /// off (nothing reads the last level's variance either) and without the reflected stream's
  /// and the glossy terms (spatialFalloff, surfaceKey, indirectDistance). The product is the
  /// one the separate pass formed from the stored colour, so the result is bit for bit the
  /// same; the level's colour and luminance are no longer written and read back.
  Plane3* remodulatedOut = nullptr;
  const std::vector<Plane>* remodulateAlbedo = nullptr;
};

/// Gersthofer's glossy weight w_r = 0.01 + sqrt(roughness(p)) (Sec. 3.4.3).
inline float roughnessWeight(float roughness) { return 0.01f + std::sqrt(std::max(0.0f, roughness)); }
/// Gersthofer Eq. 3.2: w_zi = exp(-|z_i(p) - z_i(q)| (1 - roughness(p)) / (sqrt(g3x3(Var)) + eps)).
inline float indirectDistanceWeight(float zp, float zq, float roughnessP, float filteredVariance, float eps) {
  return std::exp(-std::abs(zp - zq) * (1.0f - roughnessP) / (std::sqrt(std::max(0.0f, filteredVariance)) + eps));
}

/// c(p) of AtrousLevel::spatialFalloff for Voorhuis' Eq. 6 bandwidth sigma (<= 1, kernel
/// units): the B3 spline is close to a Gaussian of variance 1 in kernel units, and multiplying
/// it by exp(-c |k|^2) with c = 1 / (2 sigma^2) - 1/2 narrows it to about a Gaussian of
/// standard deviation sigma (down to sigma ~ 0.5; below, the integer taps fall off faster);
/// sigma = 1 leaves the kernel unchanged.
inline float glossySpatialFalloff(float sigma) {
  const float s = std::clamp(sigma, 1e-3f, 1.0f);
  return 0.5f / (s * s) - 0.5f;
}
/// Voorhuis Eq. 6: sigma_spatial = exp(-((|dP/dx| + |dP/dy|) / 2) / omega), from the mean
/// footprint (Buffer::ReflectedFootprint).
inline float glossySpatialSigma(float footprint, float omega) { return std::exp(-std::max(0.0f, footprint) / omega); }

/// One level of the filter: out(p) = sum_q h(q) w(p,q) in(q) / sum_q h(q) w(p,q), with
/// w = w_z w_n w_l; the centre tap always has w = 1. `in` and `out` must differ.
void atrousLevel(const AtrousGuide& guide, const AtrousLevel& level, const AtrousImage& in, AtrousImage& out);

/// Spatial variance estimate (Schied Sec. 4.2): for each pixel whose historyLength is below
/// `shortHistory`, var = E_w[b] - E_w[a]^2 over the (2 radius + 1)^2 window with weights
/// w_z w_n (offsets in pixels, centre weight 1; w_z's eps as AtrousLevel's); a, b are the luminance and its square, or
/// the accumulated moments (Voorhuis). Other pixels keep their `var`. radius <= a.pad.
/// `objectId` (optional): neighbours with another object id weigh 0 (Gersthofer Sec. 3.4.3:
/// "guided by differences in depth, normal and mesh ID").
void spatialVariance(const AtrousGuide& guide, const PaddedPlane& a, const PaddedPlane& b, const Plane& historyLength,
                     float shortHistory, int radius, float sigmaDepth, float depthEpsilon, float depthEpsilonRelative,
                     int normalExponent, PaddedPlane& var, const PaddedPlane* objectId = nullptr);

/// 3x3 Gaussian (binomial 1/16, 1/8, 1/4) of a plane, clamped to edge (SVGF's g3x3, run once
/// in Dundr's variant). Inside atrousLevel the same kernel reads the zero border instead.
/// `in` and `out` must differ.
void gaussian3x3(const PaddedPlane& in, PaddedPlane& out);


}  // namespace rtd
