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

// h exp(-x) as 2^(v + 1/2) for v <= -1/2: the one exponential shared by the depth, normal and
// luminance weights and the kernel weight h. The callers accumulate v = -1/2 + log2 h -
// log2(e) (x_z + x_n + x_l) with fused multiply-adds (vfnmadd, core/simd.h) onto exp2Start(h),
// the exponents' coefficients scaled by log2(e) once per pixel or per tap pair, so no product is
// ever rounded on its own and none can underflow, however small (on the FMA paths;
// core/flush.h). With v = n + g, n an integer: 2^(v + 1/2) = 2^n 2^(g + 1/2), the last factor by
// a degree-4 polynomial fitted to it (relative minimax, Remez exchange in double precision) and
// evaluated in Horner's form (four fused multiply-adds; relative error <= 2.7e-6 in float, the
// Taylor degree-5 form before had 5e-6 and cost six operations). On AVX-512, g = v - floor(v)
// in [0, 1) comes from one vreduceps and a zero-masked vscalefps applies 2^floor(v) and the
// cut in one instruction (n is never formed); the other paths take n = round(v), |g| <= 1/2,
// from the 1.5 * 2^23 rounding trick, whose integer bits also give 2^n. As |v| >= 1/2, g is 0
// or at least 2^-25 in magnitude, so Horner's products do not underflow either. Where v is below
// `cut` the result is exactly 0 (v = -inf and NaN too). The pass is bound by the FP ports'
// throughput (about 28 vector operations per tap on AVX-512), so every operation counts.
constexpr float kLog2e = 1.44269504088896341f, kLn2 = 0.693147180559945f;
/// v's starting value for a tap of kernel weight h: the -1/2 shift plus log2 h.
inline float exp2Start(float h) { return -0.5f + std::log2(h); }
/// Where v falls below it, 2^(v + 1/2) is cut to 0: the weight without h is then below
/// 2^kMinWeightExp2 (the scalar weights' bound, atrous.h).
inline float exp2Cut(float h) { return float(kMinWeightExp2) - 0.5f + std::log2(h); }
inline vf exp2Shifted(vf v, float cut = exp2Cut(1.0f)) {
#ifdef RTD_SIMD_AVX512
  // 2^(g + 1/2) on [0, 1).
  constexpr float c0 = 1.41421723f, c1 = 0.980055392f, c2 = 0.341451615f, c3 = 0.0735553131f, c4 = 0.0191402044f;
  const vf g = _mm512_reduce_ps(v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const vf p = c0 + g * (c1 + g * (c2 + g * (c3 + g * c4)));
  return _mm512_maskz_scalef_ps(_mm512_cmp_ps_mask(v, splat(cut), _CMP_GE_OQ), p, v);
#else
  // 2^(g + 1/2) on [-1/2, 1/2].
  constexpr float c0 = 1.41421247f, c1 = 0.980222285f, c2 = 0.339761198f, c3 = 0.0790797994f, c4 = 0.0135341678f;
  constexpr float kMagic = 12582912.0f;  // 1.5 * 2^23: v + kMagic rounds v to an integer
  v = vmax(v, splat(cut - 1.0f));  // NaN: the bound
  const vi keep = v >= cut;
  const vf t = v + kMagic;
  const vf n = t - kMagic;
  const vf g = v - n;
  const vf p = c0 + g * (c1 + g * (c2 + g * (c3 + g * c4)));
  // The low bits of t hold n + 2^22 (t's exponent is that of kMagic): 2^n's exponent bits.
  return p * asFloat(((asInt(t) + (127 - int(0x4b400000))) << 23) & keep);
#endif
}

// x = 1 - n(p) . n(q) with fused multiply-adds (one rounding per step, no product alone): the
// normal weight's series variable (w_n = (1 - x)^sigma_n).
inline vf oneMinusDot(vf ax, vf ay, vf az, vf bx, vf by, vf bz) {
  return vfnmadd(az, bz, vfnmadd(ay, by, vfnmadd(ax, bx, splat(1.0f))));
}
// sigma_n log2(e) (1 + x/2 + x^2/3) in Horner's form, c_i = sigma_n log2(e) / i: -log2 w_n is
// x times it (the series of atrousRowsT), which the caller subtracts with one vfnmadd.
inline vf normalSeriesFactor(vf x, float c1, float c2, float c3) { return c1 + x * (c2 + x * c3); }

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

// One level for kN streams (1 or 2) that share the guide and every geometric parameter of the
// level (kernel, step, depth and normal weights: AtrousLevel::sharesGeometry): per tap, the
// guide's loads, w_n's series and the depth term of the exponent are computed once and serve
// every stream, which adds its own luminance term and takes its own exp2. The operations of
// each stream are those of a one-stream level in the same order, so the two-stream level
// gives bit for bit the results of two one-stream levels. The per-pixel switches (sparse input,
// falloff, glossy weights, centre scale) are one-stream only.
template <int kN, bool kPropagate, bool kLogNormal, bool kMasked, bool kFalloff, bool kGlossy>
void atrousRowsT(const AtrousGuide& g, const AtrousLevel* const* lvs, const AtrousImage* const* ins,
                 AtrousImage* const* outs, const AtrousTap* taps, int tapCount, float h0) {
  static_assert(kN == 1 || !(kMasked || kFalloff || kGlossy));
  const AtrousLevel& lv = *lvs[0];  // the shared geometry, and the one-stream switches
  const PaddedPlane& z = g.depth;
  const int w = z.width;
  const float sigmaZ = lv.sigmaDepth, epsZ = lv.depthEpsilon, epsRelZ = lv.depthEpsilonRelative;
  const int e = std::max(1, lv.normalExponent);
  const float sigmaN = float(e);
  const float minCosine = std::exp2(float(kMinWeightExp2) / float(e)), kMinWeight = std::exp2(float(kMinWeightExp2));
  const float* pz = z.data.data();
  const float *pnx = g.normal[0].data.data(), *pny = g.normal[1].data.data(), *pnz = g.normal[2].data.data();
  const float *pgx = g.gradX.data.data(), *pgy = g.gradY.data.data();
  const ptrdiff_t S = z.stride;
  // Each stream's signal and luminance-weight parameters.
  struct Stream {
    const float *pr, *pg, *pb, *pl, *pv, *pscale;
    float *qr, *qg, *qb, *ql, *qv;
    float sigmaL, epsL;
    bool prefilter, useVar, cie;
    MomentLuminance luminance;
  } st[kN];
  for (int s = 0; s < kN; ++s) {
    const AtrousLevel& l = *lvs[s];
    const AtrousImage& in = *ins[s];
    AtrousImage& out = *outs[s];
    st[s] = {in.color[0].data.data(), in.color[1].data.data(), in.color[2].data.data(), in.lum.data.data(),
             in.var.data.data(), l.sigmaScale ? l.sigmaScale->data.data() : nullptr, out.color[0].data.data(),
             out.color[1].data.data(), out.color[2].data.data(), out.lum.data.data(), out.var.data.data(),
             l.sigmaLuminance, l.luminanceEpsilon, l.prefilterVariance, l.varianceScale,
             l.luminance == MomentLuminance::CieLightness, l.luminance};
  }
  const float* pvalid = kMasked ? lv.validIn->data.data() : nullptr;
  float* qvalid = kMasked ? lv.validOut->data.data() : nullptr;
  const float* pfall = kFalloff ? lv.spatialFalloff->data.data() : nullptr;
  const float* pzi = kGlossy ? lv.indirectDistance->data.data() : nullptr;
  const float* pziScale = kGlossy ? lv.indirectDistanceScale->data.data() : nullptr;
  const float* pcentre = kN == 1 && lv.centreScale ? lv.centreScale->data.data() : nullptr;
  // Each tap's starting exponent and cut (exp2Shifted), and its bound on h w_n w_z w_l.
  float start[32], cut[32], minWeight[32];
  assert(tapCount == 24 || tapCount == 8);
  for (int k = 0; k < tapCount; ++k) {
    start[k] = exp2Start(taps[k].h);
    cut[k] = exp2Cut(taps[k].h);
    minWeight[k] = taps[k].h * kMinWeight;
  }
  // The normal series' coefficients and the depth denominator in log2 units: the reciprocal
  // of ln 2 (sigma_z |grad z . o| + eps) is log2(e) / (...).
  const float cn1 = sigmaN * kLog2e, cn2 = 0.5f * sigmaN * kLog2e, cn3 = sigmaN / 3.0f * kLog2e;
  const float sigmaZ2 = sigmaZ * kLn2, epsZ2 = epsZ * kLn2, epsRelZ2 = epsRelZ * kLn2, maxDen2 = kMaxDepthDenominator * kLn2;

  stridedRows(z.height, lv.step, [&](int y) {
    for (int x = 0; x < w; x += kLanes) {
      const size_t c = z.index(x, y);
      const vf zc = load(pz + c), nx = load(pnx + c), ny = load(pny + c), nz = load(pnz + c);
      const vf gx = load(pgx + c) * sigmaZ2, gy = load(pgy + c) * sigmaZ2;
      const vf epsZc2 = epsZ2 + epsRelZ2 * vabs(zc);  // depthEpsilonAt, in log2 units
      vf lc[kN], inv[kN], ziInv, zic;
      for (int s = 0; s < kN; ++s) {
        const Stream& t = st[s];
        lc[s] = load(t.pl + c);
        // w_l bandwidth from the (3x3-Gaussian-prefiltered) variance at the centre.
        const float* pv = t.pv;
        vf v = load(pv + c);
        if (t.prefilter)
          v = 0.25f * v + 0.125f * (load(pv + c - 1) + load(pv + c + 1) + load(pv + c - S) + load(pv + c + S)) +
              0.0625f * (load(pv + c - S - 1) + load(pv + c - S + 1) + load(pv + c + S - 1) + load(pv + c + S + 1));
        v = vmax(v, splat(0.0f));
        const vf sd = t.useVar ? v : vsqrt(v);
        const vf k = t.pscale ? load(t.pscale + c) : splat(1.0f);
        inv[s] = k > 0.0f ? kLog2e / (t.sigmaL * k * sd + t.epsL) : splat(0.0f);
        if constexpr (kGlossy) {
          // Gersthofer Eq. 3.2: (1 - roughness(p)) / (sqrt(g3x3(Var)) + eps), folded into one factor.
          ziInv = load(pziScale + c) * kLog2e / ((t.useVar ? vsqrt(v) : sd) + t.epsL);
          zic = load(pzi + c);
        }
      }
      const vf fall = kFalloff ? load(pfall + c) * kLog2e : splat(0.0f);
      vf w0 = kMasked ? h0 * load(pvalid + c) : splat(h0);
      if (pcentre) w0 *= load(pcentre + c);  // w_r on every neighbour = 1/w_r on the centre
      vf sw[kN], sr[kN], sg[kN], sb[kN], sv[kN];
      for (int s = 0; s < kN; ++s) {
        sw[s] = w0, sr[s] = w0 * load(st[s].pr + c), sg[s] = w0 * load(st[s].pg + c), sb[s] = w0 * load(st[s].pb + c);
        sv[s] = kPropagate ? w0 * w0 * load(st[s].pv + c) : splat(0.0f);
      }
      // One tap: v = start - log2(e) (x_z + x_l [+ falloff] [+ x_zi] + x_n), then h w = 2^(v + 1/2).
      auto tap = [&](int k, vf depthScale) {
        const AtrousTap& t = taps[k];
        const size_t q = c + t.offset;
        const vf vz = vfnmadd(vabs(zc - load(pz + q)), depthScale, splat(start[k]));  // fused: exp2Shifted
        // w_n = d^sigma_n = exp(sigma_n ln d), -ln d = x + x^2/2 + x^3/3 + ..., x = 1 - d: the
        // series is exact to 1e-5 relative where w_n matters (d > 0.9 for sigma_n = 64) and
        // makes w_n ~ 0 where d <= 0, so it joins the one exp. Otherwise the exact power: d
        // below 2^(kMinWeightExp2 / e) gives w_n < 2^kMinWeightExp2: 0, so the powers stay
        // normal; the product w_n w_z w_l is cut at the same bound.
        vf x, series, wn;
        if constexpr (kLogNormal) {
          x = oneMinusDot(nx, ny, nz, load(pnx + q), load(pny + q), load(pnz + q));
          series = normalSeriesFactor(x, cn1, cn2, cn3);
        } else {
          const vf d = nx * load(pnx + q) + ny * load(pny + q) + nz * load(pnz + q);
          wn = ipow<-1>(d >= minCosine ? d : splat(0.0f), e);
        }
        for (int s = 0; s < kN; ++s) {
          vf v = vfnmadd(vabs(lc[s] - load(st[s].pl + q)), inv[s], vz);
          if constexpr (kFalloff) v = vfnmadd(fall, splat(t.k2), v);
          if constexpr (kGlossy) v = vfnmadd(vabs(zic - load(pzi + q)), ziInv, v);
          vf wt;
          if constexpr (kLogNormal) {
            wt = exp2Shifted(vfnmadd(x, series, v), cut[k]);
          } else {
            const vf wnzl = wn * exp2Shifted(v, cut[k]);
            wt = wnzl >= minWeight[k] ? wnzl : splat(0.0f);
          }
          if constexpr (kMasked) wt *= load(pvalid + q);
          sw[s] += wt;
          sr[s] += wt * load(st[s].pr + q);
          sg[s] += wt * load(st[s].pg + q);
          sb[s] += wt * load(st[s].pb + q);
          if constexpr (kPropagate) sv[s] += wt * wt * load(st[s].pv + q);
        }
      };
      // Taps come in opposite pairs (q, 2p - q) whose w_z denominators sigma_z |grad z . (p - q)|
      // + eps are equal: one reciprocal serves both (atrousLevel orders the list that way).
      // The 3x3 and 5x5 kernels' 8 and 24 taps as compile-time counts: fully unrolled.
      auto pair = [&](int k, int n) {
        const AtrousTap& a = taps[k];
        const vf depthScale = vrcp(vmin(vabs(gx * a.ox + gy * a.oy), splat(maxDen2)) + epsZc2);
        tap(k, depthScale);
        tap(n - 1 - k, depthScale);
      };
      auto pairs = [&](auto count) {
        constexpr int n = decltype(count)::value;
        if constexpr (kN == 1) {
#pragma GCC unroll 12
          for (int k = 0; k < n / 2; ++k) pair(k, n);
        } else {
          // Two streams: fully unrolled the body outgrows the op cache and the registers.
#pragma GCC unroll 1
          for (int k = 0; k < n / 2; ++k) pair(k, n);
        }
      };
      if (tapCount == 24) pairs(std::integral_constant<int, 24>{});
      else pairs(std::integral_constant<int, 8>{});
      for (int s = 0; s < kN; ++s) {
        const Stream& t = st[s];
        vf rcp;
        if constexpr (kMasked) {
          // Any weight that is not 0 is >= 2^-32 (core/flush.h).
          const vi any = sw[s] > 0.0f;
          const vf safe = any ? sw[s] : splat(1.0f);
          rcp = any ? 1.0f / safe : splat(0.0f);
          store(qvalid + c, any ? splat(1.0f) : splat(0.0f));
        } else {
          rcp = 1.0f / sw[s];
        }
        const vf r = vflush(sr[s] * rcp), gg = vflush(sg[s] * rcp), b = vflush(sb[s] * rcp);
        store(t.qr + c, r);
        store(t.qg + c, gg);
        store(t.qb + c, b);
        if constexpr (kPropagate) store(t.qv + c, vflush(sv[s] * rcp * rcp));
        if (!t.cie) {
          store(t.ql + c, vflush(lumVector(t.luminance, r, gg, b)));
        } else {
          float lr[kLanes], lgg[kLanes], lb[kLanes], lo[kLanes];
          store(lr, r);
          store(lgg, gg);
          store(lb, b);
          for (int k = 0; k < kLanes; ++k)
            lo[k] = flushTiny(momentLuminance(MomentLuminance::CieLightness, lr[k], lgg[k], lb[k]));
          std::memcpy(t.ql + c, lo, sizeof lo);
        }
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
  const float cn1 = sigmaN * kLog2e, cn2 = 0.5f * sigmaN * kLog2e, cn3 = sigmaN / 3.0f * kLog2e;
  const float sigmaZ2 = sigmaZ * kLn2, epsZ2 = epsZ * kLn2, epsRelZ2 = epsRelZ * kLn2, maxDen2 = kMaxDepthDenominator * kLn2;
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
      const vf gx = load(pgx + c) * sigmaZ2, gy = load(pgy + c) * sigmaZ2;
      const vf epsZc2 = epsZ2 + epsRelZ2 * vabs(zc);  // depthEpsilonAt, in log2 units
      vf sw = splat(1.0f), s1 = load(A + c), s2 = load(B + c);
      const vf idc = pid ? load(pid + c) : splat(0.0f);
      auto tap = [&](int dx, int dy, vf depthScale) {
        const size_t q = c + ptrdiff_t(dy) * S + dx;
        vf v = vfnmadd(vabs(zc - load(pz + q)), depthScale, splat(-0.5f));
        vf wt;
        if constexpr (kLogNormal) {
          const vf xx = oneMinusDot(nx, ny, nz, load(pnx + q), load(pny + q), load(pnz + q));
          wt = exp2Shifted(vfnmadd(xx, normalSeriesFactor(xx, cn1, cn2, cn3), v));
        } else {
          const vf d = nx * load(pnx + q) + ny * load(pny + q) + nz * load(pnz + q);
          const vf wn = ipow<-1>(d >= minCosine ? d : splat(0.0f), e) * exp2Shifted(v);
          wt = wn >= kMinWeight ? wn : splat(0.0f);
        }
        if (pid) wt = load(pid + q) == idc ? wt : splat(0.0f);  // the mesh-id term
        sw += wt;
        s1 += wt * load(A + q);
        s2 += wt * load(B + q);
      };
      // Opposite offsets share the depth denominator's reciprocal; the default radius 3 (48
      // taps) is unrolled at compile time.
      auto window = [&](auto radius) {
        constexpr int kR = decltype(radius)::value;
        const int r = kR > 0 ? kR : R;
#pragma GCC unroll 7
        for (int dy = -r; dy <= 0; ++dy)
#pragma GCC unroll 7
          for (int dx = -r; dx <= r; ++dx) {
            if (dy == 0 && dx >= 0) break;
            const vf depthScale = vrcp(vmin(vabs(gx * float(dx) + gy * float(dy)), splat(maxDen2)) + epsZc2);
            tap(dx, dy, depthScale);
            tap(-dx, -dy, depthScale);
          }
      };
      if (R == 3) window(std::integral_constant<int, 3>{});
      else window(std::integral_constant<int, 0>{});
      const vf m1 = s1 / sw, m2 = s2 / sw;
      const vf v = vflush(vmax(m2 - vsquareOrZero(m1), splat(0.0f)));
      for (int k = 0; k < lanes; ++k)
        if (n[x + k] < shortHistory) out[x + k] = v[k];
    }
  }, 2);
}
}  // namespace

void atrousRows(const AtrousGuide& g, const AtrousLevel* const* lvs, const AtrousImage* const* ins,
                AtrousImage* const* outs, int streams, const AtrousTap* taps, int tapCount, float h0) {
  const AtrousLevel& lv = *lvs[0];
  // The series form of w_n is accurate for large exponents (the papers' 64 and 128); small
  // ones use the exact power.
  const bool series = lv.normalExponent >= 16;
  const bool p = lv.propagateVariance, masked = lv.validIn && lv.validOut, falloff = lv.spatialFalloff;
  const bool glossy = lv.indirectDistance && lv.indirectDistanceScale;
  // One instantiation per combination of the switches (Gersthofer's glossy weights only dense:
  // his masked pixels are black samples, not holes); two streams only without the per-pixel
  // switches (atrousLevels checks).
  assert(!(glossy && masked));
  assert(streams == 1 || (streams == 2 && !masked && !falloff && !glossy && !lv.centreScale &&
                          lvs[1]->propagateVariance == p));
  using T = std::true_type;
  using F = std::false_type;
  if (streams == 2) {
    auto run2 = [&](auto prop, auto logNormal) {
      atrousRowsT<2, decltype(prop)::value, decltype(logNormal)::value, false, false, false>(g, lvs, ins, outs, taps,
                                                                                          tapCount, h0);
    };
    auto withSeries2 = [&](auto prop) { series ? run2(prop, T{}) : run2(prop, F{}); };
    p ? withSeries2(T{}) : withSeries2(F{});
    return;
  }
  auto run = [&](auto prop, auto logNormal, auto mask, auto fall, auto gl) {
    atrousRowsT<1, decltype(prop)::value, decltype(logNormal)::value, decltype(mask)::value, decltype(fall)::value,
                decltype(gl)::value>(g, lvs, ins, outs, taps, tapCount, h0);
  };
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
