// Temporal accumulation's rows for one CPU path (core/simd.h): eight pixels at a time with AVX2
// where all eight have bilinear history (Bilinear8), the scalar reference elsewhere and on the
// sse2 path.
#include <algorithm>
#include <cmath>

#include "passes/demodulation.h"
#include "passes/temporal_accumulation_kernels.h"
#include "core/simd.h"
#include "passes/bilinear8.h"

namespace rtd::RTD_SIMD_NS {

void accumulateRow(const Reprojection& rp, const Plane& length, float alpha, const float* const current[3],
                   const Plane3& history, Plane3& out, int y) {
  const int w = rp.width;
  const size_t row = size_t(y) * w;
  auto pixel = [&](int x) {
    const size_t i = row + x;
    if (rp.kind[i] == Reprojection::None) {
      for (int k = 0; k < 3; ++k) out[k].data[i] = flushTiny(current[k][x]);
      return;
    }
    const float a = newSampleWeight(length.data[i], alpha);
    for (int k = 0; k < 3; ++k) out[k].data[i] = flushTiny(a * current[k][x] + (1.0f - a) * rp.gather(history[k], i));
  };
  int x = 0;
#ifdef RTD_SIMD_AVX2
  // Eight pixels at a time where all eight have bilinear history (the same arithmetic).
  Bilinear8 taps8;
  const __m256 one = _mm256_set1_ps(1.0f), vAlpha = _mm256_set1_ps(alpha);
  const float* hPrev[3] = {history[0].ptr(), history[1].ptr(), history[2].ptr()};
  for (; x + 8 <= w; x += 8) {
    const size_t i = row + x;
    Bilinear8::prefetchRecord(rp, i);
    if (!taps8.load(rp, i)) {
      for (int k = 0; k < 8; ++k) pixel(x + k);
      continue;
    }
    for (int k = 0; k < 3; ++k) {  // as accumulateRows
      taps8.prefetch(hPrev[k]);
      prefetchAhead(current[k] + x);
      prefetchAheadForWrite(out[k].ptr() + i);
    }
    prefetchAhead(length.ptr() + i);
    const __m256 a = _mm256_max_ps(_mm256_div_ps(one, _mm256_loadu_ps(length.ptr() + i)), vAlpha);
    for (int k = 0; k < 3; ++k)
      _mm256_storeu_ps(out[k].ptr() + i, flush8(_mm256_fmadd_ps(a, _mm256_loadu_ps(current[k] + x),
                                                                    _mm256_mul_ps(_mm256_sub_ps(one, a), taps8.gather(hPrev[k])))));
  }
#endif
  for (; x < w; ++x) pixel(x);
}

void accumulateRows(const Reprojection& rp, const Plane* color, float alpha, float momentsAlpha, int maxHistoryLength,
                    const AccumulationOptions& options, const AccumulationHistory& h, int rowBegin, int rowEnd) {
  const int w = rp.width;
  const bool moments = options.moments;
  const float maxLength = float(maxHistoryLength);
  const float* mask = options.sampleMask ? options.sampleMask->ptr() : nullptr;
  const Plane* albedo = options.albedo ? options.albedo->data() : nullptr;
  Plane* current = options.current ? options.current->data() : nullptr;
  const Plane* gradient = options.temporalGradient;
  const int gradientStride = std::max(1, options.temporalGradientStride);
  const float* alphas = options.alphaPlane ? options.alphaPlane->ptr() : nullptr;
  const Plane* clipLo = options.clipLow ? options.clipLow->data() : nullptr;
  const Plane* clipHi = options.clipHigh ? options.clipHigh->data() : nullptr;
  const bool fixed = !options.cumulativeColor;
  // One fused pass per pixel: history length, colour and both moments from the same taps.
  auto pixel = [&](size_t i) {
    float c[3] = {color[0].data[i], color[1].data[i], color[2].data[i]};
    if (albedo)
      for (int k = 0; k < 3; ++k) c[k] /= demodulationFactor(albedo[k].data[i]);
    if (current)
      for (int k = 0; k < 3; ++k) current[k].data[i] = c[k];
    const float l = options.luminance == MomentLuminance::Rec709 ? luminance(c[0], c[1], c[2])
                                                                 : momentLuminance(options.luminance, c[0], c[1], c[2]);
    // The scalar path (borders, disocclusions, the 3x3 fallback): 0 where there is no history.
    const float histLength = rp.gather(h.lengthPrev, i);
    const float hist1 = moments ? rp.gather(h.m1Prev, i) : 0.0f, hist2 = moments ? rp.gather(h.m2Prev, i) : 0.0f;
    float hist[3];
    for (int k = 0; k < 3; ++k) hist[k] = rp.gather(h.colorPrev[k], i);
    if (clipLo)  // clip before the blend (Voorhuis Sec. 4.2.3)
      for (int k = 0; k < 3; ++k) hist[k] = std::min(std::max(hist[k], clipLo[k].data[i]), clipHi[k].data[i]);
    // Disoccluded pixels have history length 0 here, hence n = 1 and weight 1.
    const bool none = rp.kind[i] == Reprojection::None;
    if (gradient) {
      // A-SVGF: the history shrinks where the shading changed, N' = min(N (1-G)^e + 1, cap),
      // and the new sample weighs mix(max(1/N', floor), 1, G).
      const int x = int(i % size_t(w)), y = int(i / size_t(w));
      const float g = std::clamp((*gradient)(x / gradientStride, y / gradientStride), 0.0f, 1.0f);
      const float n = adaptiveHistoryLength(none ? 0.0f : histLength, g, options.historyExponent, maxLength);
      const float a = adaptiveAlpha(n, g, alpha), am = adaptiveAlpha(n, g, momentsAlpha);
      h.length.data[i] = n;
      for (int k = 0; k < 3; ++k) h.color[k].data[i] = flushTiny(a * c[k] + (1.0f - a) * hist[k]);
      if (moments) {
        h.m1.data[i] = flushTiny(am * l + (1.0f - am) * hist1);
        h.m2.data[i] = flushTiny(am * squareOrZero(l) + (1.0f - am) * hist2);
      }
      return;
    }
    const float n = none ? 1.0f : std::min(std::round(histLength) + 1.0f, maxLength);
    // Fixed weights (Gersthofer): alpha wherever there is history, 1 where there is none
    // (reprojection failed, or the taps hold no data yet: n = 1).
    const float floorAlpha = alphas ? alphas[i] : alpha;
    const float a = fixed ? (n <= 1.0f ? 1.0f : floorAlpha) : newSampleWeight(n, floorAlpha);
    // Moments: cumulative-then-EMA like the colour (Voorhuis Sec. 6), or a plain EMA
    // wherever there is history (Schied et al. 2017).
    const float am = fixed ? (n <= 1.0f ? 1.0f : momentsAlpha)
                           : options.cumulativeMoments ? newSampleWeight(n, momentsAlpha) : (none ? 1.0f : momentsAlpha);
    if (mask && mask[i] == 0.0f) {
      // No sample this frame (Dundr Sec. 5): the history carries over unchanged; without
      // history the pixel stays missing (length 0).
      h.length.data[i] = none ? 0.0f : std::round(histLength);
      for (int k = 0; k < 3; ++k) h.color[k].data[i] = flushTiny(hist[k]);
      if (moments) {
        h.m1.data[i] = flushTiny(hist1);
        h.m2.data[i] = flushTiny(hist2);
      }
      return;
    }
    h.length.data[i] = n;
    for (int k = 0; k < 3; ++k) h.color[k].data[i] = flushTiny(a * c[k] + (1.0f - a) * hist[k]);
    if (moments) {
      h.m1.data[i] = flushTiny(am * l + (1.0f - am) * hist1);
      h.m2.data[i] = flushTiny(am * squareOrZero(l) + (1.0f - am) * hist2);
    }
  };
  // Eight pixels at a time where all eight have bilinear history and, with a sample mask, a
  // sample (the same arithmetic; A-SVGF's gradient for integral exponents, historyShrink's
  // squarings in the same order). (CIE L* has no vector form here: its moments take the scalar
  // path; without moments the luminance is not needed.)
  const float e = options.historyExponent;
  const bool integralExponent = e == std::floor(e) && e >= 0.0f && e <= 64.0f;
  [[maybe_unused]] const bool vectorized =
      (!gradient || integralExponent) && (options.luminance != MomentLuminance::CieLightness || !moments);
  for (int y = rowBegin; y < rowEnd; ++y) {
    int x = 0;
#ifdef RTD_SIMD_AVX2
    if (vectorized) {
      const float *lenPrev = h.lengthPrev.ptr(), *m1Prev = h.m1Prev.ptr(), *m2Prev = h.m2Prev.ptr();
      const float* cPrev[3] = {h.colorPrev[0].ptr(), h.colorPrev[1].ptr(), h.colorPrev[2].ptr()};
      const __m256 one = _mm256_set1_ps(1.0f), half = _mm256_set1_ps(0.5f), maxLen = _mm256_set1_ps(maxLength);
      const __m256 vAlpha = _mm256_set1_ps(alpha), vMomentsAlpha = _mm256_set1_ps(momentsAlpha);
      const bool rec601 = options.luminance == MomentLuminance::Rec601;
      const __m256 lr = _mm256_set1_ps(rec601 ? 0.299f : 0.2126f), lg = _mm256_set1_ps(rec601 ? 0.587f : 0.7152f),
                   lb = _mm256_set1_ps(rec601 ? 0.114f : 0.0722f);
      Bilinear8 taps8;
      for (; x + 8 <= w; x += 8) {
        const size_t i = size_t(y) * w + x;
        Bilinear8::prefetchRecord(rp, i);
        // A pixel without a sample this frame (mask 0; the renderer writes a mask of ones at
        // 1 spp) keeps its history: the scalar path.
        const bool sampled = !mask || _mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(mask + i), _mm256_setzero_ps(),
                                                                       _CMP_EQ_OQ)) == 0;
        if (!sampled || !taps8.load(rp, i)) {
          for (int k = 0; k < 8; ++k) pixel(i + k);
          continue;
        }
        // The history rows, the current colour and the outputs ahead (kPrefetchAhead); the
        // moments' planes only where they exist.
        for (const float* q : {lenPrev, cPrev[0], cPrev[1], cPrev[2]}) taps8.prefetch(q);
        for (int k = 0; k < 3; ++k) prefetchAhead(color[k].ptr() + i);
        if (albedo)  // demodulated here: its loads waited on memory (a fifth of the pass's samples)
          for (int k = 0; k < 3; ++k) prefetchAhead(albedo[k].ptr() + i);
        for (float* q : {h.length.ptr(), h.color[0].ptr(), h.color[1].ptr(), h.color[2].ptr()}) prefetchAheadForWrite(q + i);
        if (moments) {
          taps8.prefetch(m1Prev), taps8.prefetch(m2Prev);
          prefetchAheadForWrite(h.m1.ptr() + i), prefetchAheadForWrite(h.m2.ptr() + i);
        }
        const __m256 len = taps8.gather(lenPrev);
        __m256 n, a, am;
        if (gradient) {
          // A-SVGF: N' = min(N (1 - G)^e + 1, max), weights mix(max(1/N', floor), 1, G).
          float gv[8];
          const float* grow = gradient->row(y / gradientStride);
          for (int k = 0; k < 8; ++k) gv[k] = std::clamp(grow[(x + k) / gradientStride], 0.0f, 1.0f);
          const __m256 g = _mm256_loadu_ps(gv);
          __m256 shrink = one, d = _mm256_sub_ps(one, g);
          for (int k = int(e); k; k >>= 1) {
            if (k & 1) shrink = _mm256_mul_ps(shrink, d);
            d = _mm256_mul_ps(d, d);
          }
          n = _mm256_min_ps(_mm256_add_ps(_mm256_mul_ps(len, shrink), one), maxLen);
          const __m256 invN = _mm256_div_ps(one, n);
          const __m256 a0 = _mm256_max_ps(invN, vAlpha), am0 = _mm256_max_ps(invN, vMomentsAlpha);
          a = _mm256_add_ps(a0, _mm256_mul_ps(_mm256_sub_ps(one, a0), g));
          am = _mm256_add_ps(am0, _mm256_mul_ps(_mm256_sub_ps(one, am0), g));
        } else {
          // n = min(round(history length) + 1, max), round half away from zero as std::round.
          __m256 rounded = _mm256_round_ps(len, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
          rounded = _mm256_add_ps(rounded, _mm256_and_ps(_mm256_cmp_ps(_mm256_sub_ps(len, rounded), half, _CMP_GE_OQ), one));
          n = _mm256_min_ps(_mm256_add_ps(rounded, one), maxLen);
          const __m256 invN = _mm256_div_ps(one, n);
          const __m256 floorAlpha = alphas ? _mm256_loadu_ps(alphas + i) : vAlpha;
          // Fixed weights (Gersthofer): alpha, or 1 where the taps hold no data yet (n = 1).
          const __m256 first = _mm256_cmp_ps(n, one, _CMP_LE_OQ);
          a = fixed ? _mm256_blendv_ps(floorAlpha, one, first) : _mm256_max_ps(invN, floorAlpha);
          am = fixed                       ? _mm256_blendv_ps(vMomentsAlpha, one, first)
               : options.cumulativeMoments ? _mm256_max_ps(invN, vMomentsAlpha)
                                           : vMomentsAlpha;
        }
        _mm256_storeu_ps(h.length.ptr() + i, n);
        __m256 c[3];
        for (int k = 0; k < 3; ++k) {
          c[k] = _mm256_loadu_ps(color[k].ptr() + i);
          if (albedo) {
            const __m256 a = _mm256_loadu_ps(albedo[k].ptr() + i);
            c[k] = _mm256_div_ps(c[k], _mm256_blendv_ps(one, a, _mm256_cmp_ps(a, _mm256_set1_ps(kAlbedoEpsilon), _CMP_GT_OQ)));
          }
          if (current) _mm256_storeu_ps(current[k].ptr() + i, c[k]);
          __m256 hist = taps8.gather(cPrev[k]);
          if (clipLo)
            hist = _mm256_min_ps(_mm256_max_ps(hist, _mm256_loadu_ps(clipLo[k].ptr() + i)), _mm256_loadu_ps(clipHi[k].ptr() + i));
          _mm256_storeu_ps(h.color[k].ptr() + i,
                           flush8(_mm256_fmadd_ps(a, c[k], _mm256_mul_ps(_mm256_sub_ps(one, a), hist))));
        }
        if (!moments) continue;
        const __m256 l = _mm256_fmadd_ps(lb, c[2], _mm256_fmadd_ps(lg, c[1], _mm256_mul_ps(lr, c[0])));
        const __m256 bm = _mm256_sub_ps(one, am);
        _mm256_storeu_ps(h.m1.ptr() + i, flush8(_mm256_fmadd_ps(am, l, _mm256_mul_ps(bm, taps8.gather(m1Prev)))));
        _mm256_storeu_ps(h.m2.ptr() + i,
                         flush8(_mm256_fmadd_ps(am, squareOrZero8(l), _mm256_mul_ps(bm, taps8.gather(m2Prev)))));
      }
    }
#endif
    for (; x < w; ++x) pixel(size_t(y) * w + x);
  }
}

}  // namespace rtd::RTD_SIMD_NS
