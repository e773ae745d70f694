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
#include "passes/demodulation.h"
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
// Taylor degree-5 form before had 5e-6 and cost six operations; SSE2, without FMA, uses
// Estrin's form, whose chain is shorter). As |v| >= 1/2, g is 0 or at least 2^-25 in magnitude,
// so Horner's products do not underflow either.
//
// The weight h w it returns is exactly 0 where it would be below 2^kMinWeightExp2 (v below
// kExp2Cut; v = -inf and NaN too), else at least that: normal, and so are its products with
// stored values (core/flush.h). On AVX-512, g = v - floor(v) in [0, 1) comes from one vreduceps
// and a zero-masked vscalefps applies 2^floor(v) and the cut in one instruction (n is never
// formed). The other paths clamp v at kExp2Low and take n = round(v), |g| <= 1/2, from the
// 1.5 * 2^23 rounding trick, whose integer bits give 2^n as an exponent field offset by
// kExp2Bias: n + kExp2Bias >= 0, and its lowest value, where v is below the cut, is the field of
// 0.0, so the cut needs no compare (the polynomial's coefficients carry 2^(127 - kExp2Bias) to
// make up for the offset). About 28 vector operations per tap on AVX-512, ~30 on AVX2.
constexpr float kLog2e = 1.44269504088896341f, kLn2 = 0.693147180559945f;
/// v's starting value for a tap of kernel weight h: the -1/2 shift plus log2 h.
inline float exp2Start(float h) { return -0.5f + std::log2(h); }
/// Where v falls below it, 2^(v + 1/2) is cut to 0: h w below 2^kMinWeightExp2.
constexpr float kExp2Cut = float(kMinWeightExp2) - 0.5f;
/// The round-to-integer paths: v clamped here rounds to n = kMinWeightExp2 - 1, whose exponent
/// field n + kExp2Bias is 0.
constexpr int kExp2Bias = 1 - kMinWeightExp2;
constexpr float kExp2Low = float(kMinWeightExp2 - 1);
// 2^(v + 1/2) of N independent arguments at once, stage by stage: each stage's N operations
// are independent and stand next to each other in the instruction stream (a tap's chain from
// its loads to its weight is ~20 dependent operations). Together with computing a pixel's
// weights before its sums (atrousRowsT) this took the AVX2 level from ~40 to ~35 cycles per
// tap on Zen 2 ("Session 8, speed" in docs/performance.md).
template <int N> inline void exp2ShiftedN(vf (&v)[N]) {
#ifdef RTD_SIMD_AVX512
  // 2^(g + 1/2) on [0, 1).
  constexpr float c0 = 1.41421723f, c1 = 0.980055392f, c2 = 0.341451615f, c3 = 0.0735553131f, c4 = 0.0191402044f;
  vf g[N], p[N];
  for (int j = 0; j < N; ++j) g[j] = _mm512_reduce_ps(v[j], _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  for (int j = 0; j < N; ++j) p[j] = c3 + g[j] * c4;
  for (int j = 0; j < N; ++j) p[j] = c2 + g[j] * p[j];
  for (int j = 0; j < N; ++j) p[j] = c1 + g[j] * p[j];
  for (int j = 0; j < N; ++j) p[j] = c0 + g[j] * p[j];
  for (int j = 0; j < N; ++j)
    v[j] = _mm512_maskz_scalef_ps(_mm512_cmp_ps_mask(v[j], splat(kExp2Cut), _CMP_GE_OQ), p[j], v[j]);
#else
  // 2^(g + 1/2) on [-1/2, 1/2], times 2^(127 - kExp2Bias) (exact: a power of two).
  constexpr float k = 0x1p102f;
  static_assert(127 - kExp2Bias == 102, "k is 2^(127 - kExp2Bias)");
  constexpr float c0 = 1.41421247f * k, c1 = 0.980222285f * k, c2 = 0.339761198f * k, c3 = 0.0790797994f * k,
                  c4 = 0.0135341678f * k;
  // 1.5 * 2^23 + kExp2Bias: v + kMagic rounds v + kExp2Bias to an integer (kMagic's ulp is 1).
  constexpr float kMagic = 12582912.0f + float(kExp2Bias);
  vf t[N], g[N], p[N];
  for (int j = 0; j < N; ++j) v[j] = vmax(v[j], splat(kExp2Low));  // NaN: the bound
  for (int j = 0; j < N; ++j) t[j] = v[j] + kMagic;
  for (int j = 0; j < N; ++j) g[j] = v[j] - (t[j] - kMagic);
#ifdef RTD_SIMD_AVX2
  for (int j = 0; j < N; ++j) p[j] = c3 + g[j] * c4;
  for (int j = 0; j < N; ++j) p[j] = c2 + g[j] * p[j];
  for (int j = 0; j < N; ++j) p[j] = c1 + g[j] * p[j];
  for (int j = 0; j < N; ++j) p[j] = c0 + g[j] * p[j];
#else
  // Without FMA, Estrin's form: a shorter chain of separate multiplies and adds than Horner's.
  for (int j = 0; j < N; ++j) {
    const vf g2 = g[j] * g[j];
    p[j] = (c0 + g[j] * c1) + g2 * ((c2 + g[j] * c3) + g2 * c4);
  }
#endif
  // t's bits are 0x4b400000 + n + kExp2Bias (its exponent is kMagic's), and 0x4b400000's low
  // nine bits are 0: shifted by 23, n + kExp2Bias (in [0, kExp2Bias]) is the exponent field of
  // 2^(n - 127 + kExp2Bias) and the rest falls off the top.
  static_assert((0x4b400000 & 0x1ff) == 0 && kExp2Bias < 0x100, "t << 23 is (n + kExp2Bias) << 23");
  for (int j = 0; j < N; ++j) v[j] = p[j] * asFloat(asInt(t[j]) << 23);
#endif
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
// into contiguous chunks: successive rows of a chunk share all but one of their tap rows, so a
// level with a large step reads each input row from memory about once instead of 2r + 1 times
// (in row order the rows y +- r step would have left the cache before they are used again).
// Levels whose tap rows come back within kRowOrderMaxSpan rows (2 r step: a row is a tap row
// of the centres from r step rows above it to r step rows below) go in row order all the
// same: their rows are still in L2 or L3 when they come back (1.5 MiB of the nine planes read
// at the taps at 1280 px), and each of the window's rows is read right after the row above
// it, which the hardware prefetcher follows. Measured against the strided order
// (BM_AtrousLevel, docs/performance.md "Session 22"): 3x3 steps 4, 8 and 16 0.86-0.98 of
// their time, 5x5 step 2 0.89 (session 21) and steps 4 and 8 0.94-1.02 (in svgf's pipeline
// 0.92-0.95), but the 5x5 step 16 (a 64-row span) 1.05; at 1920 px the 32-row spans still gain.
constexpr int kRowOrderMaxSpan = 32;
template <class Fn> void stridedRows(int height, int step, int radius, Fn&& fn) {
  if (2 * radius * step <= kRowOrderMaxSpan) step = 1;
  const int perResidue = (height + step - 1) / step;
  tbb::parallel_for(tbb::blocked_range<int>(0, perResidue * step, 2), [&](const tbb::blocked_range<int>& r) {
    for (int k = r.begin(); k != r.end(); ++k) {
      const int y = k / perResidue + (k % perResidue) * step;
      if (y < height) fn(y);
    }
  });
}

// kReflection: the reflected stream's terms (Voorhuis), each where its plane is given: Eq. 6's
// falloff and the surface key. Their own instantiation keeps every other stream's loop free of
// them (a run-time test in the common loop cost it 5-8 %).
// What a level writes: colour and luminance (plain), also the propagated variance, or the
// remodulated colour alone (AtrousLevel::remodulatedOut). A compile-time switch: tested at run
// time per group of pixels, the fused output's branch slowed every other level by 6-30 %
// (BM_AtrousLevel; docs/performance.md, "Session 15").
enum class LevelOutput { plain, propagate, remodulated };

// Whether a level of `tapCount` taps adds each pair's taps into its sums right after their
// weights, or computes all its weights first (into an array in L1) and then the sums. The sums
// after each pair save the weights' round trip through L1 where the registers hold the five sums
// beside the pair's chains: AVX-512's 32 with the 5x5 kernel (BM_AtrousLevel avx512, one thread,
// steps 1-16: 0.87-0.99; docs/performance.md, "Session 28"). AVX2 has 16 vector registers, and
// the five sums, the nine centre values and the exp's constants together (~25) made GCC spill and
// reload ~20 values per tap, the sums among them ("Session 8, speed"; on Zen 5 the sums after
// each pair measured 1.03-1.10 there); AVX-512's 3x3 kernel keeps its weights first too
// (1.02-1.15).
constexpr bool sumsFollowPairs(int tapCount) { return kLanes == 16 && tapCount == 24; }

template <LevelOutput kOut, bool kLogNormal, bool kMasked, bool kReflection, bool kGlossy>
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
  const float* pfall = kReflection && lv.spatialFalloff ? lv.spatialFalloff->data.data() : nullptr;
  const float* pzi = kGlossy ? lv.indirectDistance->data.data() : nullptr;
  const float* pziScale = kGlossy ? lv.indirectDistanceScale->data.data() : nullptr;
  const float* pcentre = lv.centreScale ? lv.centreScale->data.data() : nullptr;
  const float* pkey = kReflection && lv.surfaceKey ? lv.surfaceKey->data.data() : nullptr;
  constexpr bool kPropagate = kOut == LevelOutput::propagate;
  Plane3* remodulated = lv.remodulatedOut;
  const std::vector<Plane>* albedo = lv.remodulateAlbedo;
  // A key difference (>= 1) lowers a tap's exponent far below every cut: its weight is 0.
  constexpr float kKeyPenalty = 1e4f;
  // Each tap's starting exponent (exp2ShiftedN).
  float start[32];
  assert(tapCount == 24 || tapCount == 8);
  // The pairs' depth denominators (`pairs` below) take tap k of the first half at (-dx, -dy)
  // kernel units, dx = r - k % (2r + 1), dy = r - k / (2r + 1): atrousLevel's list, row by row
  // (the contract in atrous_kernels.h, asserted where atrousLevel builds the list).
  for (int k = 0; k < tapCount; ++k) start[k] = exp2Start(taps[k].h);
  // The normal series' coefficients and the depth denominator in log2 units: the reciprocal
  // of ln 2 (sigma_z |grad z . o| + eps) is log2(e) / (...).
  const float cn1 = sigmaN * kLog2e, cn2 = 0.5f * sigmaN * kLog2e, cn3 = sigmaN / 3.0f * kLog2e;
  const float sigmaZStep2 = sigmaZ * kLn2 * float(lv.step), epsZ2 = epsZ * kLn2, epsRelZ2 = epsRelZ * kLn2,
              maxDen2 = kMaxDepthDenominator * kLn2;

  const int radius = kernelRadius(lv.kernel);
  stridedRows(z.height, lv.step, radius, [&](int y) {
    // The lowest tap row is the one row of the window that no row before this one in
    // stridedRows' order read (in the strided order the row just before read the others; in
    // the row order of smaller spans, the row `step` before): its planes ahead
    // (kPrefetchAhead), with the centre row's own planes. The 3x3 kernel's eight taps make a
    // short loop body, in which eleven prefetches per group of pixels cost more than they
    // bring: on the 8-lane paths (two groups per cache line) it asks once per line
    // (BM_AtrousLevel avx2 3x3 0.90-0.97; every group 1.00, none 1.05; the 5x5 kernel keeps
    // every group: asking once per line was 1.0 at step 1 and up to 1.2 at step 8).
    const ptrdiff_t newRow = ptrdiff_t(z.index(0, y)) + ptrdiff_t(radius) * lv.step * S;
    for (int x = 0; x < w; x += kLanes) {
      const size_t c = z.index(x, y);
      if (kLanes == 16 || tapCount == 24 || x % 16 == 0) {
        for (const float* q : {pz, pnx, pny, pnz, pl, pr, pg, pb, pv}) prefetchAhead(q + newRow + x);
        for (const float* q : {pgx, pgy}) prefetchAhead(q + c);
      }
      const vf zc = load(pz + c), nx = load(pnx + c), ny = load(pny + c), nz = load(pnz + c);
      // sigma_z grad z times the step, in log2 units: the pairs' |grad z . o| below are sums of
      // these and their doubles (o = step (dx, dy)).
      const vf gx = load(pgx + c) * sigmaZStep2, gy = load(pgy + c) * sigmaZStep2;
      const vf epsZc2 = epsZ2 + epsRelZ2 * vabs(zc);  // depthEpsilonAt, in log2 units
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
        inv = k > 0.0f ? kLog2e / (sigmaL * k * sd + epsL) : splat(0.0f);
        if constexpr (kGlossy) {
          // Gersthofer Eq. 3.2: (1 - roughness(p)) / (sqrt(g3x3(Var)) + eps), folded into one factor.
          ziInv = load(pziScale + c) * kLog2e / ((useVar ? vsqrt(v) : sd) + epsL);
          zic = load(pzi + c);
        }
      }
      const vf fall = pfall ? load(pfall + c) * kLog2e : splat(0.0f);
      const vf keyc = pkey ? load(pkey + c) : splat(0.0f);
      vf w0 = kMasked ? h0 * load(pvalid + c) : splat(h0);
      if (pcentre) w0 *= load(pcentre + c);  // w_r on every neighbour = 1/w_r on the centre
      vf sw = w0, sr = w0 * load(pr + c), sg = w0 * load(pg + c), sb = w0 * load(pb + c);
      vf sv = kPropagate ? w0 * w0 * load(pv + c) : splat(0.0f);
      vf weights[24];
      // One pair of opposite taps ka, kb: v = start - log2(e) (x_z + x_l [+ falloff] [+ x_zi] +
      // x_n), then h w = 2^(v + 1/2). The two taps' chains are written stage by stage (each
      // line's two operations are independent; exp2ShiftedN says why), the sums in tap order.
      auto tapPair = [&](int ka, int kb, vf depthScale) __attribute__((always_inline)) {
        const int kk[2] = {ka, kb};
        size_t q[2];
        vf v[2], wt[2];
        for (int j = 0; j < 2; ++j) q[j] = c + taps[kk[j]].offset;
        for (int j = 0; j < 2; ++j)
          v[j] = vfnmadd(vabs(zc - load(pz + q[j])), depthScale, splat(start[kk[j]]));  // fused: exp2ShiftedN
        for (int j = 0; j < 2; ++j) v[j] = vfnmadd(vabs(lc - load(pl + q[j])), inv, v[j]);
        if constexpr (kReflection)
          if (pfall)
            for (int j = 0; j < 2; ++j) v[j] = vfnmadd(fall, splat(taps[kk[j]].k2), v[j]);
        if constexpr (kGlossy)
          for (int j = 0; j < 2; ++j) v[j] = vfnmadd(vabs(zic - load(pzi + q[j])), ziInv, v[j]);
        if constexpr (kReflection)
          if (pkey)
            for (int j = 0; j < 2; ++j) v[j] = vfnmadd(vabs(keyc - load(pkey + q[j])), splat(kKeyPenalty), v[j]);
        if constexpr (kLogNormal) {
          // w_n = d^sigma_n = exp(sigma_n ln d), -ln d = x + x^2/2 + x^3/3 + ..., x = 1 - d: the
          // series is exact to 1e-5 relative where w_n matters (d > 0.9 for sigma_n = 64) and
          // makes w_n ~ 0 where d <= 0, so it joins the one exp. x = 1 - n(p) . n(q) and the
          // series sigma_n log2(e) (x + x^2/2 + x^3/3) in Horner's form, all with fused
          // multiply-adds (no product rounded on its own), each stage for both taps.
          vf x[2], s[2];
          for (int j = 0; j < 2; ++j) x[j] = vfnmadd(nx, load(pnx + q[j]), splat(1.0f));
          for (int j = 0; j < 2; ++j) x[j] = vfnmadd(ny, load(pny + q[j]), x[j]);
          for (int j = 0; j < 2; ++j) x[j] = vfnmadd(nz, load(pnz + q[j]), x[j]);
          for (int j = 0; j < 2; ++j) s[j] = cn2 + x[j] * cn3;
          for (int j = 0; j < 2; ++j) s[j] = cn1 + x[j] * s[j];
          for (int j = 0; j < 2; ++j) v[j] = vfnmadd(x[j], s[j], v[j]);
          exp2ShiftedN<2>(v);
          for (int j = 0; j < 2; ++j) wt[j] = v[j];
        } else {
          // d below 2^(kMinWeightExp2 / e) gives w_n < 2^kMinWeightExp2: 0, so the powers
          // stay normal; the product h w_n w_z w_l is cut at the same bound.
          exp2ShiftedN<2>(v);
          for (int j = 0; j < 2; ++j) {
            const vf d = nx * load(pnx + q[j]) + ny * load(pny + q[j]) + nz * load(pnz + q[j]);
            const vf wn = ipow<-1>(d >= minCosine ? d : splat(0.0f), e) * v[j];
            wt[j] = wn >= kMinWeight ? wn : splat(0.0f);
          }
        }
        if constexpr (kMasked)
          for (int j = 0; j < 2; ++j) wt[j] *= load(pvalid + q[j]);
        for (int j = 0; j < 2; ++j) weights[kk[j]] = wt[j];
      };
      // One tap's share of the sums. Taken in the order of the pairs (tap k, then its opposite),
      // so the result is bit for bit that of one tap after the other wherever the sums are taken.
      auto sumTap = [&](int k) __attribute__((always_inline)) {
        const size_t q = c + taps[k].offset;
        const vf wt = weights[k];
        sw += wt;
        sr += wt * load(pr + q);
        sg += wt * load(pg + q);
        sb += wt * load(pb + q);
        if constexpr (kPropagate) sv += wt * wt * load(pv + q);
      };
      // Taps come in opposite pairs (q, 2p - q) whose w_z denominators sigma_z |grad z . (p - q)|
      // + eps are equal: one reciprocal serves both (atrousLevel orders the list that way).
      // The 3x3 and 5x5 kernels' 8 and 24 taps as compile-time counts: fully unrolled.
      // With 16 vector registers (avx2, sse2) the pairs' reciprocals come first, into
      // `depthScales` (in L1), so that the gradient and epsilon are not live across the taps:
      // fewer spills (BM_AtrousLevel avx2 0.90-0.97). AVX-512's 32 registers hold them (there
      // the split measured 0.97-1.10).
      constexpr bool kScalesFirst = kLanes < 16;
      auto pairs = [&](auto count) {
        constexpr int n = decltype(count)::value;
        // Pair k's taps are (-dx, -dy) and (dx, dy) in kernel units, dy >= 0 (atrousLevel's
        // list, row by row): |grad z . o| = |dx gx + dy gy|, gx and gy already times the step,
        // from them and their doubles by one addition (the step a power of two, the products are
        // exact: the value the fused multiply-add gave), and its reciprocal by one division: the
        // divider is a unit of its own, where the estimate's Newton step and the products took
        // four operations of the two multiply pipes (BM_AtrousLevel avx2 0.93-0.99, avx512
        // 0.86-1.0; the additions with the estimate kept 0.94-1.02: docs/performance.md,
        // "Session 26").
        constexpr int kWidth = n == 24 ? 5 : 3, kRadius = kWidth / 2;
        const vf gx2 = gx + gx, gy2 = gy + gy;
        auto depthScale = [&](int k) __attribute__((always_inline)) {
          const int dx = -(k % kWidth - kRadius), dy = kRadius - k / kWidth;
          const vf ax = dx == 0 ? splat(0.0f) : (dx == 1 || dx == -1 ? gx : gx2);
          const vf ay = dy == 1 ? gy : gy2;
          const vf d = dy == 0 ? ax : dx == 0 ? ay : dx > 0 ? ay + ax : ay - ax;
          return 1.0f / (vmin(vabs(d), splat(maxDen2)) + epsZc2);
        };
        vf depthScales[n / 2];
        if constexpr (kScalesFirst) {
#pragma GCC unroll 12
          for (int k = 0; k < n / 2; ++k) depthScales[k] = depthScale(k);
        }
#pragma GCC unroll 12
        for (int k = 0; k < n / 2; ++k) {
          tapPair(k, n - 1 - k, kScalesFirst ? depthScales[k] : depthScale(k));
          if constexpr (sumsFollowPairs(n)) {
            sumTap(k);
            sumTap(n - 1 - k);
          }
        }
        // Otherwise the sums after all the weights, which wait in `weights` (in L1).
        if constexpr (!sumsFollowPairs(n)) {
#pragma GCC unroll 12
          for (int k = 0; k < n / 2; ++k) {
            sumTap(k);
            sumTap(n - 1 - k);
          }
        }
      };
      if (tapCount == 24) pairs(std::integral_constant<int, 24>{});
      else pairs(std::integral_constant<int, 8>{});
      vf rcp;
      if constexpr (kMasked) {
        // Any weight that is not 0 is >= 2^-24 (core/flush.h).
        const vi any = sw > 0.0f;
        const vf safe = any ? sw : splat(1.0f);
        rcp = any ? 1.0f / safe : splat(0.0f);
        store(qvalid + c, any ? splat(1.0f) : splat(0.0f));
      } else {
        rcp = 1.0f / sw;
      }
      const vf r = vflush(sr * rcp), gg = vflush(sg * rcp), b = vflush(sb * rcp);
      if constexpr (kPropagate) store(qv + c, vflush(sv * rcp * rcp));
      if constexpr (kOut == LevelOutput::remodulated) {
        // AtrousLevel::remodulatedOut: colour * albedo' into the frame's (unpadded) planes; the
        // row's tail is copied through a buffer, so nothing is read or written past its end.
        const int n = std::min(kLanes, w - x);
        const vf rgb[3] = {r, gg, b};
        for (int k = 0; k < 3; ++k) {
          float* o = (*remodulated)[k].row(y) + x;
          vf v = rgb[k];
          if (albedo) {
            const float* a = (*albedo)[k].row(y) + x;
            prefetchAhead(a);  // read once per frame here: from memory
            vf av = splat(1.0f);
            if (n == kLanes) av = load(a);
            else { float t[kLanes] = {}; std::memcpy(t, a, sizeof(float) * n); av = load(t); }
            v *= av > kAlbedoEpsilon ? av : splat(1.0f);  // demodulationFactor
          }
          if (n == kLanes) store(o, v);
          else { float t[kLanes]; store(t, v); std::memcpy(o, t, sizeof(float) * n); }
        }
        continue;
      }
      store(qr + c, r);
      store(qg + c, gg);
      store(qb + c, b);
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
      // As in atrousRowsT: the weights of up to kChunk opposite pairs first, both taps of a pair
      // stage by stage (exp2ShiftedN), then their sums, in the order of the taps.
      constexpr int kChunk = 7;
      vf weights[2 * kChunk];
      ptrdiff_t offsets[2 * kChunk];
      auto pairWeights = [&](int i, int dx, int dy, vf depthScale) __attribute__((always_inline)) {
        size_t q[2];
        vf v[2], wt[2];
        q[0] = c + ptrdiff_t(dy) * S + dx;
        q[1] = c - ptrdiff_t(dy) * S - dx;
        offsets[2 * i] = q[0];
        offsets[2 * i + 1] = q[1];
        for (int j = 0; j < 2; ++j) v[j] = vfnmadd(vabs(zc - load(pz + q[j])), depthScale, splat(-0.5f));
        if constexpr (kLogNormal) {
          vf xx[2], sr[2];
          for (int j = 0; j < 2; ++j) xx[j] = vfnmadd(nx, load(pnx + q[j]), splat(1.0f));
          for (int j = 0; j < 2; ++j) xx[j] = vfnmadd(ny, load(pny + q[j]), xx[j]);
          for (int j = 0; j < 2; ++j) xx[j] = vfnmadd(nz, load(pnz + q[j]), xx[j]);
          for (int j = 0; j < 2; ++j) sr[j] = cn2 + xx[j] * cn3;
          for (int j = 0; j < 2; ++j) sr[j] = cn1 + xx[j] * sr[j];
          for (int j = 0; j < 2; ++j) v[j] = vfnmadd(xx[j], sr[j], v[j]);
          exp2ShiftedN<2>(v);
          for (int j = 0; j < 2; ++j) wt[j] = v[j];
        } else {
          exp2ShiftedN<2>(v);
          for (int j = 0; j < 2; ++j) {
            const vf d = nx * load(pnx + q[j]) + ny * load(pny + q[j]) + nz * load(pnz + q[j]);
            const vf wn = ipow<-1>(d >= minCosine ? d : splat(0.0f), e) * v[j];
            wt[j] = wn >= kMinWeight ? wn : splat(0.0f);
          }
        }
        if (pid)
          for (int j = 0; j < 2; ++j) wt[j] = load(pid + q[j]) == idc ? wt[j] : splat(0.0f);  // the mesh-id term
        weights[2 * i] = wt[0];
        weights[2 * i + 1] = wt[1];
      };
      auto chunkSums = [&](int count) __attribute__((always_inline)) {
        for (int i = 0; i < 2 * count; ++i) {
          const size_t q = offsets[i];
          const vf wt = weights[i];
          sw += wt;
          s1 += wt * load(A + q);
          s2 += wt * load(B + q);
        }
      };
      // Opposite offsets share the depth denominator's reciprocal, here the estimate (a division
      // as in atrousRowsT measured no gain on this pass: docs/performance.md, "Session 26");
      // the default radius 3 (48 taps) is unrolled at compile time.
      auto window = [&](auto radius) {
        constexpr int kR = decltype(radius)::value;
        const int r = kR > 0 ? kR : R;
#pragma GCC unroll 7
        for (int dy = -r; dy <= 0; ++dy) {
          int i = 0;
#pragma GCC unroll 7
          for (int dx = -r; dx <= r; ++dx) {
            if (dy == 0 && dx >= 0) break;
            const vf depthScale = vrcp(vmin(vabs(gx * float(dx) + gy * float(dy)), splat(maxDen2)) + epsZc2);
            pairWeights(i++, dx, dy, depthScale);
            if (i == kChunk) {
              chunkSums(i);
              i = 0;
            }
          }
          if (i) chunkSums(i);
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

void atrousRows(const AtrousGuide& g, const AtrousLevel& lv, const AtrousImage& in, AtrousImage& out,
                const AtrousTap* taps, int tapCount, float h0) {
  // The series form of w_n is accurate for large exponents (the papers' 64 and 128); small
  // ones use the exact power.
  const bool series = lv.normalExponent >= 16;
  const bool masked = lv.validIn && lv.validOut;
  assert(!(lv.remodulatedOut && lv.propagateVariance));  // the last level's variance: read by nothing
  const bool reflection = lv.spatialFalloff || lv.surfaceKey;
  const bool glossy = lv.indirectDistance && lv.indirectDistanceScale;
  // One instantiation per combination of the switches (Gersthofer's glossy weights only dense:
  // his masked pixels are black samples, not holes).
  assert(!(glossy && masked));
  auto run = [&](auto output, auto logNormal, auto mask, auto fall, auto gl) {
    atrousRowsT<decltype(output)::value, decltype(logNormal)::value, decltype(mask)::value, decltype(fall)::value,
                decltype(gl)::value>(g, lv, in, out, taps, tapCount, h0);
  };
  using T = std::true_type;
  using F = std::false_type;
  auto withFalloff = [&](auto output, auto logNormal, auto mask, auto gl) {
    reflection ? run(output, logNormal, mask, T{}, gl) : run(output, logNormal, mask, F{}, gl);
  };
  auto withMask = [&](auto output, auto logNormal) {
    if (glossy) withFalloff(output, logNormal, F{}, T{});
    else masked ? withFalloff(output, logNormal, T{}, F{}) : withFalloff(output, logNormal, F{}, F{});
  };
  auto withSeries = [&](auto output) { series ? withMask(output, T{}) : withMask(output, F{}); };
  using O = LevelOutput;
  if (lv.remodulatedOut) {
    // Only the plain weights (SVGF's one stream; AtrousLevel::remodulatedOut): four more
    // instantiations per path, not twelve.
    assert(!reflection && !glossy);
    const std::integral_constant<O, O::remodulated> r;
    if (series) masked ? run(r, T{}, T{}, F{}, F{}) : run(r, T{}, F{}, F{}, F{});
    else masked ? run(r, F{}, T{}, F{}, F{}) : run(r, F{}, F{}, F{}, F{});
  } else if (lv.propagateVariance) {
    withSeries(std::integral_constant<O, O::propagate>{});
  } else {
    withSeries(std::integral_constant<O, O::plain>{});
  }
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
