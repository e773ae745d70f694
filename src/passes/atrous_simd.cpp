// The a-trous filter's hot loops for one CPU path (core/simd.h): atrousLevel and
// spatialVariance (atrous.cpp) call them through RTD_SIMD. kLanes pixels at a time (4, 8 or 16),
// all taps accumulated in registers.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "core/parallel.h"
#include "passes/atrous_kernels.h"
#include "core/simd.h"

namespace rtd::RTD_SIMD_NS {

namespace {

// factor * exp(-x) from xs = x + kExpShift, x >= 0: one exp shared by the depth, normal and
// luminance weights. The weights' exponents are sums of products (|z_p - z_q| / denominator,
// |l_p - l_q| / bandwidth, the normal series); accumulating them onto kExpShift with fused
// multiply-adds means no product is ever rounded on its own, so none can underflow, however
// small (with FMA; core/flush.h). Then exp(-x) = 2^(v + 1/2) with v = -xs log2(e) <= -1/2,
// v = n + g, n = round(v), |g| <= 1/2, and 2^(g + 1/2) = sqrt(2) e^(g ln 2) by its degree-5
// Taylor polynomial in Estrin's form (relative error <= 5e-6). As |v| >= 1/2, g is 0 or at
// least 2^-25 in magnitude, so the polynomial's powers of g do not underflow either. Where 2^u
// is below 2^kMinWeightExp2 the result is exactly 0 (x = +inf and NaN too): the exponent's bits
// are masked to zero. The mask and 2^n are off the critical path. The pass is bound by the
// latency of this chain (a tap's weight is ~20 dependent operations), so its depth matters
// more than its operation count.
constexpr float kExpShift = 0.5f * 0.693147180559945f;
inline vf expNegShifted(vf xs, vf factor = vf{} + 1.0f) {
  constexpr float kBound = float(kMinWeightExp2) - 1.5f;
  const vf v = vmax(xs * -1.44269504088896341f, splat(kBound));  // NaN: the bound
  const vi keep = v >= float(kMinWeightExp2) - 0.5f;
  const vf n = vround(v);
  const vf g = v - n;
  constexpr float r2 = 1.41421356237309505f, l1 = 0.693147180559945f, l2 = l1 * l1 / 2, l3 = l2 * l1 / 3,
                  l4 = l3 * l1 / 4, l5 = l4 * l1 / 5;
  const vf g2 = g * g;
  const vf p = (r2 + g * (r2 * l1)) + g2 * ((r2 * l2 + g * (r2 * l3)) + g2 * (r2 * l4 + g * (r2 * l5)));
  const vf scale = asFloat(((__builtin_convertvector(n, vi) + 127) << 23) & keep);
  return p * (scale * factor);  // factor * exp(-x): the product with the factor off the chain
}

// d^e by repeated squaring; kSquarings >= 0: e = 2^kSquarings, unrolled (sigma_n = 128 is
// seven squarings, 64 six).
template <int kSquarings> inline vf ipow(vf d, int e) {
  if constexpr (kSquarings >= 0) {
    for (int i = 0; i < kSquarings; ++i) d *= d;
    return d;
  }
  vf r = splat(1.0f);
  while (true) {
    if (e & 1) r *= d;
    e >>= 1;
    if (!e) return r;
    d *= d;
  }
}

inline vf lumVector(MomentLuminance m, vf r, vf g, vf b) {
  if (m == MomentLuminance::Rec601) return 0.299f * r + 0.587f * g + 0.114f * b;
  return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}

// fn(y) for every row, in the order y = r, r + step, r + 2 step, ... for r = 0 .. step-1, split
// into contiguous chunks: successive rows of a chunk share four of their five tap rows, so a
// level with a large step reads each input row from memory about once instead of five times
// (in row order the rows y +- 2 step would have left the cache before they are used again).
template <class Fn> void stridedRows(int height, int step, Fn&& fn) {
  const int perResidue = (height + step - 1) / step;
  tbb::parallel_for(tbb::blocked_range<int>(0, perResidue * step, 2), [&](const tbb::blocked_range<int>& r) {
    for (int k = r.begin(); k != r.end(); ++k) {
      const int y = k / perResidue + (k % perResidue) * step;
      if (y < height) fn(y);
    }
  });
}

template <bool kPropagate, bool kLogNormal, bool kMasked, bool kFalloff, bool kGlossy>
void atrousRowsT(const AtrousGuide& g, const AtrousLevel& lv, const AtrousImage& in, AtrousImage& out,
                const AtrousTap* taps, int tapCount, float h0) {
  const PaddedPlane& z = g.depth;
  const int w = z.width;
  const float sigmaZ = lv.sigmaDepth, epsZ = lv.depthEpsilon, epsRelZ = lv.depthEpsilonRelative;
  const int e = std::max(1, lv.normalExponent);
  const float sigmaN = float(e);
  const float minCosine = std::exp2(float(kMinWeightExp2) / float(e)), kMinWeight = std::exp2(float(kMinWeightExp2));
  const float* pz = z.data.data();
  const float *pnx = g.normal[0].data.data(), *pny = g.normal[1].data.data(), *pnz = g.normal[2].data.data();
  const float *pgx = g.gradX.data.data(), *pgy = g.gradY.data.data();
  const float *pr = in.color[0].data.data(), *pg = in.color[1].data.data(), *pb = in.color[2].data.data();
  const float *pl = in.lum.data.data(), *pv = in.var.data.data();
  const float* pscale = lv.sigmaScale ? lv.sigmaScale->data.data() : nullptr;
  const ptrdiff_t S = z.stride;
  const float sigmaL = lv.sigmaLuminance, epsL = lv.luminanceEpsilon;
  const bool prefilter = lv.prefilterVariance, useVar = lv.varianceScale;
  float *qr = out.color[0].data.data(), *qg = out.color[1].data.data(), *qb = out.color[2].data.data();
  float *ql = out.lum.data.data(), *qv = out.var.data.data();
  const bool cie = lv.luminance == MomentLuminance::CieLightness;
  const float* pvalid = kMasked ? lv.validIn->data.data() : nullptr;
  float* qvalid = kMasked ? lv.validOut->data.data() : nullptr;
  const float* pfall = kFalloff ? lv.spatialFalloff->data.data() : nullptr;
  const float* pzi = kGlossy ? lv.indirectDistance->data.data() : nullptr;
  const float* pziScale = kGlossy ? lv.indirectDistanceScale->data.data() : nullptr;
  const float* pcentre = lv.centreScale ? lv.centreScale->data.data() : nullptr;

  stridedRows(z.height, lv.step, [&](int y) {
    for (int x = 0; x < w; x += kLanes) {
      const size_t c = z.index(x, y);
      const vf zc = load(pz + c), nx = load(pnx + c), ny = load(pny + c), nz = load(pnz + c);
      const vf gx = load(pgx + c) * sigmaZ, gy = load(pgy + c) * sigmaZ;
      const vf epsZc = epsZ + epsRelZ * vabs(zc);  // depthEpsilonAt
      const vf lc = load(pl + c);
      vf inv, ziInv, zic;
      {
        // w_l bandwidth from the (3x3-Gaussian-prefiltered) variance at the centre.
        vf v = load(pv + c);
        if (prefilter)
          v = 0.25f * v + 0.125f * (load(pv + c - 1) + load(pv + c + 1) + load(pv + c - S) + load(pv + c + S)) +
              0.0625f * (load(pv + c - S - 1) + load(pv + c - S + 1) + load(pv + c + S - 1) + load(pv + c + S + 1));
        v = vmax(v, splat(0.0f));
        const vf sd = useVar ? v : vsqrt(v);
        const vf k = pscale ? load(pscale + c) : splat(1.0f);
        inv = k > 0.0f ? 1.0f / (sigmaL * k * sd + epsL) : splat(0.0f);
        if constexpr (kGlossy) {
          // Gersthofer Eq. 3.2: (1 - roughness(p)) / (sqrt(g3x3(Var)) + eps), folded into one factor.
          ziInv = load(pziScale + c) / ((useVar ? vsqrt(v) : sd) + epsL);
          zic = load(pzi + c);
        }
      }
      const vf fall = kFalloff ? load(pfall + c) : splat(0.0f);
      vf w0 = kMasked ? h0 * load(pvalid + c) : splat(h0);
      if (pcentre) w0 *= load(pcentre + c);  // w_r on every neighbour = 1/w_r on the centre
      vf sw = w0, sr = w0 * load(pr + c), sg = w0 * load(pg + c), sb = w0 * load(pb + c);
      vf sv = kPropagate ? w0 * w0 * load(pv + c) : splat(0.0f);
      auto tap = [&](const AtrousTap& t, vf depthScale) {
        const size_t q = c + t.offset;
        const vf d = nx * load(pnx + q) + ny * load(pny + q) + nz * load(pnz + q);
        vf expo = kExpShift + vabs(zc - load(pz + q)) * depthScale;  // fused: expNegShifted
        expo = expo + vabs(lc - load(pl + q)) * inv;
        if constexpr (kFalloff) expo += fall * t.k2;
        if constexpr (kGlossy) expo += vabs(zic - load(pzi + q)) * ziInv;
        vf wt;
        if constexpr (kLogNormal) {
          // w_n = d^sigma_n = exp(sigma_n ln d), -ln d = x + x^2/2 + x^3/3 + ..., x = 1 - d: the
          // series is exact to 1e-5 relative where w_n matters (d > 0.9 for sigma_n = 64) and
          // makes w_n ~ 0 where d <= 0, so it joins the one exp.
          // Evaluated as expo + sigma_n x + x^2 (sigma_n/2 + sigma_n x/3): three steps deep.
          const vf x = 1.0f - d;
          expo = (expo + sigmaN * x) + (x * x) * (0.5f * sigmaN + x * (sigmaN / 3.0f));
          wt = expNegShifted(expo, splat(t.h));
        } else {
          // d below 2^(kMinWeightExp2 / e) gives w_n < 2^kMinWeightExp2: 0, so the powers
          // stay normal; the product with w_z w_l is cut at the same bound.
          const vf wn = ipow<-1>(d >= minCosine ? d : splat(0.0f), e) * expNegShifted(expo);
          wt = t.h * (wn >= kMinWeight ? wn : splat(0.0f));
        }
        if constexpr (kMasked) wt *= load(pvalid + q);
        sw += wt;
        sr += wt * load(pr + q);
        sg += wt * load(pg + q);
        sb += wt * load(pb + q);
        if constexpr (kPropagate) sv += wt * wt * load(pv + q);
      };
      // Taps come in opposite pairs (q, 2p - q) whose w_z denominators sigma_z |grad z . (p - q)|
      // + eps are equal: one reciprocal serves both (atrousLevel orders the list that way).
      for (int k = 0, n = tapCount; k < n / 2; ++k) {
        const AtrousTap& a = taps[k];
        const vf depthScale = vrcp(vmin(vabs(gx * a.ox + gy * a.oy), splat(kMaxDepthDenominator)) + epsZc);
        tap(a, depthScale);
        tap(taps[n - 1 - k], depthScale);
      }
      vf rcp;
      if constexpr (kMasked) {
        // Any weight that is not 0 is >= 2^-32 (core/flush.h).
        const vi any = sw > 0.0f;
        const vf safe = any ? sw : splat(1.0f);
        rcp = any ? 1.0f / safe : splat(0.0f);
        store(qvalid + c, any ? splat(1.0f) : splat(0.0f));
      } else {
        rcp = 1.0f / sw;
      }
      const vf r = vflush(sr * rcp), gg = vflush(sg * rcp), b = vflush(sb * rcp);
      store(qr + c, r);
      store(qg + c, gg);
      store(qb + c, b);
      if constexpr (kPropagate) store(qv + c, vflush(sv * rcp * rcp));
      if (!cie) {
        store(ql + c, vflush(lumVector(lv.luminance, r, gg, b)));
      } else {
        float lr[kLanes], lgg[kLanes], lb[kLanes], lo[kLanes];
        store(lr, r);
        store(lgg, gg);
        store(lb, b);
        for (int k = 0; k < kLanes; ++k) lo[k] = flushTiny(momentLuminance(MomentLuminance::CieLightness, lr[k], lgg[k], lb[k]));
        std::memcpy(ql + c, lo, sizeof lo);
      }
    }
  });
}


template <bool kLogNormal>
void spatialVarianceRowsT(const AtrousGuide& g, const PaddedPlane& pa, const PaddedPlane& pb, const Plane& len,
                         float shortHistory, int R, float sigmaZ, float epsZ, float epsRelZ, int e, PaddedPlane& var,
                         const PaddedPlane* objectId) {
  const float* pid = objectId ? objectId->data.data() : nullptr;
  const PaddedPlane& z = g.depth;
  const int w = z.width;
  const ptrdiff_t S = z.stride;
  const float sigmaN = float(e);
  const float minCosine = std::exp2(float(kMinWeightExp2) / float(e)), kMinWeight = std::exp2(float(kMinWeightExp2));
  const float* pz = z.data.data();
  const float *pnx = g.normal[0].data.data(), *pny = g.normal[1].data.data(), *pnz = g.normal[2].data.data();
  const float *pgx = g.gradX.data.data(), *pgy = g.gradY.data.data();
  const float *A = pa.data.data(), *B = pb.data.data();
  parallelRows(z.height, [&](int y) {
    const float* n = len.row(y);
    float* out = var.row(y);
    for (int x = 0; x < w; x += kLanes) {
      const int lanes = std::min(kLanes, w - x);
      bool any = false;
      for (int k = 0; k < lanes; ++k) any |= n[x + k] < shortHistory;
      if (!any) continue;  // long histories keep the temporal variance
      const size_t c = z.index(x, y);
      const vf zc = load(pz + c), nx = load(pnx + c), ny = load(pny + c), nz = load(pnz + c);
      const vf gx = load(pgx + c) * sigmaZ, gy = load(pgy + c) * sigmaZ;
      const vf epsZc = epsZ + epsRelZ * vabs(zc);  // depthEpsilonAt
      vf sw = splat(1.0f), s1 = load(A + c), s2 = load(B + c);
      const vf idc = pid ? load(pid + c) : splat(0.0f);
      for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx) {
          if (!dx && !dy) continue;
          const size_t q = c + ptrdiff_t(dy) * S + dx;
          const vf d = nx * load(pnx + q) + ny * load(pny + q) + nz * load(pnz + q);
          vf expo = kExpShift + vabs(zc - load(pz + q)) *
                                    vrcp(vmin(vabs(gx * float(dx) + gy * float(dy)), splat(kMaxDepthDenominator)) + epsZc);
          vf wt;
          if constexpr (kLogNormal) {
            const vf xx = 1.0f - d;
            expo = (expo + sigmaN * xx) + (xx * xx) * (0.5f * sigmaN + xx * (sigmaN / 3.0f));
            wt = expNegShifted(expo);
          } else {
            const vf wn = ipow<-1>(d >= minCosine ? d : splat(0.0f), e) * expNegShifted(expo);
            wt = wn >= kMinWeight ? wn : splat(0.0f);
          }
          if (pid) wt = load(pid + q) == idc ? wt : splat(0.0f);  // the mesh-id term
          sw += wt;
          s1 += wt * load(A + q);
          s2 += wt * load(B + q);
        }
      const vf m1 = s1 / sw, m2 = s2 / sw;
      const vf v = vflush(vmax(m2 - vsquareOrZero(m1), splat(0.0f)));
      for (int k = 0; k < lanes; ++k)
        if (n[x + k] < shortHistory) out[x + k] = v[k];
    }
  }, 2);
}
}  // namespace

void atrousRows(const AtrousGuide& g, const AtrousLevel& lv, const AtrousImage& in, AtrousImage& out,
                const AtrousTap* taps, int tapCount, float h0) {
  // The series form of w_n is accurate for large exponents (the papers' 64 and 128); small
  // ones use the exact power.
  const bool series = lv.normalExponent >= 16;
  const bool p = lv.propagateVariance, masked = lv.validIn && lv.validOut, falloff = lv.spatialFalloff;
  const bool glossy = lv.indirectDistance && lv.indirectDistanceScale;
  // One instantiation per combination of the switches (Gersthofer's glossy weights only dense:
  // his masked pixels are black samples, not holes).
  assert(!(glossy && masked));
  auto run = [&](auto prop, auto logNormal, auto mask, auto fall, auto gl) {
    atrousRowsT<decltype(prop)::value, decltype(logNormal)::value, decltype(mask)::value, decltype(fall)::value,
                decltype(gl)::value>(g, lv, in, out, taps, tapCount, h0);
  };
  using T = std::true_type;
  using F = std::false_type;
  auto withFalloff = [&](auto prop, auto logNormal, auto mask, auto gl) {
    falloff ? run(prop, logNormal, mask, T{}, gl) : run(prop, logNormal, mask, F{}, gl);
  };
  auto withMask = [&](auto prop, auto logNormal) {
    if (glossy) withFalloff(prop, logNormal, F{}, T{});
    else masked ? withFalloff(prop, logNormal, T{}, F{}) : withFalloff(prop, logNormal, F{}, F{});
  };
  auto withSeries = [&](auto prop) { series ? withMask(prop, T{}) : withMask(prop, F{}); };
  p ? withSeries(T{}) : withSeries(F{});
}

void spatialVarianceRows(const AtrousGuide& g, const PaddedPlane& a, const PaddedPlane& b, const Plane& len,
                         float shortHistory, int R, float sigmaDepth, float depthEpsilon, float depthEpsilonRelative, int e,
                         PaddedPlane& var, const PaddedPlane* objectId) {
  if (e >= 16)
    spatialVarianceRowsT<true>(g, a, b, len, shortHistory, R, sigmaDepth, depthEpsilon, depthEpsilonRelative, e, var, objectId);
  else
    spatialVarianceRowsT<false>(g, a, b, len, shortHistory, R, sigmaDepth, depthEpsilon, depthEpsilonRelative, e, var, objectId);
}

}  // namespace rtd::RTD_SIMD_NS
