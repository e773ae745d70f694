// Import's and export's per-row loops for one CPU path (core/simd.h): AVX2 de-interleave and
// interleave of 2-, 3- and 4-float pixels on the avx2 and avx512 paths; the scalar reference
// (Bounds::sanitize) for tails and on the sse2 path.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/frame_data_kernels.h"
#include "core/simd.h"

namespace rtd::RTD_SIMD_NS {

namespace {
#ifdef RTD_SIMD_AVX2
// sanitize8's counts, per lane (each lane counts the values it saw), summed into SanitizeCounts
// once per row: counting with a movemask and a popcount per vector cost import ~2 ms of its
// 7.7 at 1280x720 (docs/performance.md, "Session 10").
struct LaneCounts {
  __m256i nonFinite, outOfRange;
  static uint64_t sum(__m256i v) {
    alignas(32) uint32_t lane[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(lane), v);
    uint64_t n = 0;
    for (uint32_t k : lane) n += k;
    return n;
  }
  void addTo(SanitizeCounts& bad) const {
    bad.nonFinite += sum(nonFinite);
    bad.outOfRange += sum(outOfRange);
  }
};

// Bounds::sanitize on eight lanes, deciding on the bits as sanitizeValue does.
inline __m256 sanitize8(__m256 v, Bounds b, LaneCounts& bad) {
  const __m256i magnitude = _mm256_and_si256(_mm256_castps_si256(v), _mm256_set1_epi32(0x7fffffff));
  const __m256i nonFinite = _mm256_cmpgt_epi32(magnitude, _mm256_set1_epi32(int(Bounds::kMaxBits)));
  const __m256i keep = _mm256_andnot_si256(nonFinite, _mm256_cmpgt_epi32(magnitude, _mm256_set1_epi32(int(Bounds::kTinyBits) - 1)));
  v = _mm256_and_ps(v, _mm256_castsi256_ps(keep));  // non-finite and tiny values 0
  const __m256 clamped = _mm256_min_ps(_mm256_max_ps(v, _mm256_set1_ps(b.lo)), _mm256_set1_ps(b.hi));
  const __m256i changed = _mm256_castps_si256(_mm256_cmp_ps(clamped, v, _CMP_NEQ_OQ));  // v is never NaN here
  bad.nonFinite = _mm256_sub_epi32(bad.nonFinite, nonFinite);  // a mask lane is -1
  bad.outOfRange = _mm256_sub_epi32(bad.outOfRange, _mm256_andnot_si256(nonFinite, changed));
  return clamped;
}

// The channels of eight pixels of `stride` (2, 3 or 4) floats each into out[0..stride).
// stride 3: v0 = r0 g0 b0 r1 g1 b1 r2 g2, v1 = b2 r3 ... r5, v2 = g5 b5 ... b7; channel c of
// pixel j is element 3j + c, so each channel is two blends (lanes from v0, v1, v2) and one
// lane permutation. stride 2 and 4: in-lane shuffles, then a cross-lane permutation.
inline void deinterleave8(const float* src, int stride, __m256 out[4]) {
  if (stride == 3) {
    const __m256 v0 = _mm256_loadu_ps(src), v1 = _mm256_loadu_ps(src + 8), v2 = _mm256_loadu_ps(src + 16);
    // lanes of v1 (first blend) and v2 (second blend) that hold channel c
    const __m256 r = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0b10010010), v2, 0b00100100);
    const __m256 g = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0b00100100), v2, 0b01001001);
    const __m256 b = _mm256_blend_ps(_mm256_blend_ps(v0, v1, 0b01001001), v2, 0b10010010);
    out[0] = _mm256_permutevar8x32_ps(r, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    out[1] = _mm256_permutevar8x32_ps(g, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    out[2] = _mm256_permutevar8x32_ps(b, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
  } else if (stride == 2) {
    const __m256 v0 = _mm256_loadu_ps(src), v1 = _mm256_loadu_ps(src + 8);
    // x0 x1 x4 x5 | x2 x3 x6 x7 -> x0 .. x7
    out[0] = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(v0, v1, 0x88)), 0xD8));
    out[1] = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(v0, v1, 0xDD)), 0xD8));
  } else {
    const __m256 v[4] = {_mm256_loadu_ps(src), _mm256_loadu_ps(src + 8), _mm256_loadu_ps(src + 16), _mm256_loadu_ps(src + 24)};
    deinterleave4x8(v, out);
  }
}
#endif

#ifdef RTD_SIMD_AVX2
// importFloatRow's 8-pixel loop for pixels of kStride floats (1: no emission) from pixel x0 to
// the last whole group of eight; returns the next x.
template <int kStride>
int importRow8(const float* src, int x0, int nc, float* const* dst, int w, Bounds b, bool stream, const RowFixes& fixes,
               SanitizeCounts& bad, bool& offUnit) {
  const float* const* e = fixes.emission;
  nc = std::min(nc, kStride);  // (nc <= kStride always; tells the compiler too)
  for (int c = 0; c < nc; ++c) stream = stream && reinterpret_cast<uintptr_t>(dst[c]) % 32 == 0;
  LaneCounts counts{_mm256_setzero_si256(), _mm256_setzero_si256()};
  __m256 off = _mm256_setzero_ps();
  int x = x0;
  for (; x + 8 <= w; x += 8) {
    __m256 v[4];
    if constexpr (kStride == 1) v[0] = _mm256_loadu_ps(src + x);
    else deinterleave8(src + size_t(x) * kStride, kStride, v);
    for (int c = 0; c < nc; ++c) {
      v[c] = sanitize8(v[c], b, counts);
      if (e) v[c] = _mm256_max_ps(flush8(_mm256_sub_ps(v[c], _mm256_loadu_ps(e[c] + x))), _mm256_setzero_ps());
    }
    if (kStride >= 3 && fixes.unitVectors) {
      const __m256 l2 = _mm256_add_ps(_mm256_add_ps(squareOrZero8(v[0]), squareOrZero8(v[1])), squareOrZero8(v[2]));
      const __m256 dev = _mm256_and_ps(_mm256_sub_ps(l2, _mm256_set1_ps(1.0f)), _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
      const __m256 zero = _mm256_setzero_ps();
      const __m256 some = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(v[0], zero, _CMP_NEQ_UQ), _mm256_cmp_ps(v[1], zero, _CMP_NEQ_UQ)),
                                       _mm256_cmp_ps(v[2], zero, _CMP_NEQ_UQ));
      off = _mm256_or_ps(off, _mm256_and_ps(some, _mm256_cmp_ps(dev, _mm256_set1_ps(kUnitCheckTolerance), _CMP_GT_OQ)));
    }
    for (int c = 0; c < nc; ++c) {
      if (stream) _mm256_stream_ps(dst[c] + x, v[c]);
      else _mm256_storeu_ps(dst[c] + x, v[c]);
    }
  }
  if (stream) streamFence();  // the streamed stores are weakly ordered: complete them before the row is handed on
  counts.addTo(bad);
  offUnit = offUnit || _mm256_movemask_ps(off) != 0;
  return x;
}
#endif

#ifdef RTD_SIMD_AVX512
// Sixteen lanes: sanitize8's rule on mask registers, the counts per lane.
inline vf sanitize16(vf v, Bounds b, __m512i& nonFiniteCount, __m512i& outOfRangeCount) {
  const __m512i magnitude = _mm512_and_si512(_mm512_castps_si512(v), _mm512_set1_epi32(0x7fffffff));
  const __mmask16 nonFinite = _mm512_cmpgt_epi32_mask(magnitude, _mm512_set1_epi32(int(Bounds::kMaxBits)));
  const __mmask16 keep = _mm512_mask_cmpgt_epi32_mask(__mmask16(~nonFinite), magnitude, _mm512_set1_epi32(int(Bounds::kTinyBits) - 1));
  v = _mm512_maskz_mov_ps(keep, v);  // non-finite and tiny values 0
  const vf clamped = vmin(vmax(v, splat(b.lo)), splat(b.hi));
  const __mmask16 changed = _mm512_mask_cmp_ps_mask(__mmask16(~nonFinite), clamped, v, _CMP_NEQ_OQ);
  const __m512i one = _mm512_set1_epi32(1);
  nonFiniteCount = _mm512_mask_add_epi32(nonFiniteCount, nonFinite, nonFiniteCount, one);
  outOfRangeCount = _mm512_mask_add_epi32(outOfRangeCount, changed, outOfRangeCount, one);
  return clamped;
}

// Permutation indices for deinterleave16: channel c of pixel j is element kStride j + c of the
// 16 pixels' floats. kPart 0: from floats [0, 32) (two-source index into v0 || v1, 0 where the
// element lies beyond); kPart 1, stride 3: lane j of the first result where it holds the
// element, else float 32 + i as 16 + i (v2); kPart 1, stride 4: floats [32, 64) into v2 || v3.
template <int kStride, int kChannel, int kPart> inline __m512i deinterleaveIndex() {
  alignas(64) int32_t i[16];
  for (int j = 0; j < 16; ++j) {
    const int at = kStride * j + kChannel;
    if (kPart == 0) i[j] = at < 32 ? at : 0;
    else if (kStride == 3) i[j] = at < 32 ? j : 16 + at - 32;
    else i[j] = at >= 32 ? at - 32 : 0;
  }
  return _mm512_load_si512(i);
}
template <int kStride, int kChannel> inline vf deinterleaveChannel(vf v0, vf v1, vf v2, vf v3) {
  const vf low = _mm512_permutex2var_ps(v0, deinterleaveIndex<kStride, kChannel, 0>(), v1);
  if constexpr (kStride == 2) return low;
  else if constexpr (kStride == 3) return _mm512_permutex2var_ps(low, deinterleaveIndex<3, kChannel, 1>(), v2);
  else return _mm512_mask_blend_ps(0xff00, low, _mm512_permutex2var_ps(v2, deinterleaveIndex<4, kChannel, 1>(), v3));
}
// The first nc channels of 16 pixels of kStride (2, 3 or 4) floats into out[0..nc): two-source
// permutations of the 32 or 64 floats (one per channel for stride 2, two for stride 3, two
// and a blend for stride 4) where the 8-lane path takes three instructions per eight pixels.
template <int kStride> inline void deinterleave16(const float* src, int nc, vf out[4]) {
  const vf v0 = load(src), v1 = load(src + 16);
  const vf v2 = kStride >= 3 ? load(src + 32) : v0, v3 = kStride == 4 ? load(src + 48) : v0;
  out[0] = deinterleaveChannel<kStride, 0>(v0, v1, v2, v3);
  out[1] = deinterleaveChannel<kStride, 1>(v0, v1, v2, v3);
  if constexpr (kStride >= 3) out[2] = deinterleaveChannel<kStride, 2>(v0, v1, v2, v3);
  if constexpr (kStride == 4)
    if (nc == 4) out[3] = deinterleaveChannel<4, 3>(v0, v1, v2, v3);
}

// importFloatRow's 16-pixel loop for pixels of kStride floats (1: no emission), of which the first
// nc are the channels: pixels [0, 16k) of the row; returns the next x. The same operations as
// the 8-lane loop, in the same order per value.
template <int kStride>
int importRow16(const float* src, int nc, float* const* dst, int w, Bounds b, bool stream, const RowFixes& fixes,
                SanitizeCounts& bad, bool& offUnit) {
  const float* const* e = fixes.emission;
  for (int c = 0; c < nc; ++c) stream = stream && streamAligned(dst[c]);
  __m512i nonFinite = _mm512_setzero_si512(), outOfRange = _mm512_setzero_si512();
  __mmask16 off = 0;
  int x = 0;
  for (; x + 16 <= w; x += 16) {
    vf v[4];
    if constexpr (kStride == 1) v[0] = load(src + x);
    else deinterleave16<kStride>(src + size_t(x) * kStride, nc, v);
    for (int c = 0; c < nc; ++c) {
      v[c] = sanitize16(v[c], b, nonFinite, outOfRange);
      if (e) v[c] = vmax(vflush(v[c] - load(e[c] + x)), splat(0.0f));
    }
    if (kStride >= 3 && fixes.unitVectors) {
      const vf l2 = vsquareOrZero(v[0]) + vsquareOrZero(v[1]) + vsquareOrZero(v[2]);
      const __mmask16 some = _mm512_cmp_ps_mask(v[0], splat(0.0f), _CMP_NEQ_UQ) | _mm512_cmp_ps_mask(v[1], splat(0.0f), _CMP_NEQ_UQ) |
                             _mm512_cmp_ps_mask(v[2], splat(0.0f), _CMP_NEQ_UQ);
      off |= some & _mm512_cmp_ps_mask(vabs(l2 - 1.0f), splat(kUnitCheckTolerance), _CMP_GT_OQ);
    }
    for (int c = 0; c < nc; ++c) {
      if (stream) streamStore(dst[c] + x, v[c]);
      else store(dst[c] + x, v[c]);
    }
  }
  if (stream) streamFence();  // the streamed stores are weakly ordered: complete them before the row is handed on
  bad.nonFinite += uint64_t(_mm512_reduce_add_epi32(nonFinite));
  bad.outOfRange += uint64_t(_mm512_reduce_add_epi32(outOfRange));
  offUnit = offUnit || off != 0;
  return x;
}
#endif

}  // namespace

bool importFloatRow(const float* src, int stride, int nc, float* const* dst, int w, Bounds b, bool stream,
                    const RowFixes& fixes, SanitizeCounts& bad) {
  const float* const* e = fixes.emission;
  int x = 0;
  bool offUnit = false;
#ifdef RTD_SIMD_AVX512
  // Sixteen pixels at a time (the 8-lane loop below takes the rest of the row): svgf's import at
  // 1280x720, two threads, 4.8 -> 3.5 ms (docs/performance.md, "Session 10").
  if (stride == 4) x = importRow16<4>(src, nc, dst, w, b, stream, fixes, bad, offUnit);
  else if (stride == 3) x = importRow16<3>(src, nc, dst, w, b, stream, fixes, bad, offUnit);
  else if (stride == 2) x = importRow16<2>(src, nc, dst, w, b, stream, fixes, bad, offUnit);
  else if (stride == 1 && !e) x = importRow16<1>(src, nc, dst, w, b, stream, fixes, bad, offUnit);
#endif
#ifdef RTD_SIMD_AVX2
  // The stride as a compile-time argument, as the 16-lane loop: with it a run-time value, the
  // de-interleave's branches and the channel loops stayed in the 8-pixel loop.
  if (stride == 4) x = importRow8<4>(src, x, nc, dst, w, b, stream, fixes, bad, offUnit);
  else if (stride == 3) x = importRow8<3>(src, x, nc, dst, w, b, stream, fixes, bad, offUnit);
  else if (stride == 2) x = importRow8<2>(src, x, nc, dst, w, b, stream, fixes, bad, offUnit);
  else if (stride == 1 && !e) x = importRow8<1>(src, x, nc, dst, w, b, stream, fixes, bad, offUnit);
#endif
  for (; x < w; ++x) {
    float v[4];
    for (int c = 0; c < nc; ++c) {
      v[c] = b.sanitize(src[size_t(x) * stride + c], bad);
      if (e) v[c] = std::max(0.0f, flushTiny(v[c] - e[c][x]));
      dst[c][x] = v[c];
    }
    if (fixes.unitVectors) {
      const float l2 = squareOrZero(v[0]) + squareOrZero(v[1]) + squareOrZero(v[2]);
      offUnit |= std::abs(l2 - 1.0f) > kUnitCheckTolerance && (v[0] != 0.0f || v[1] != 0.0f || v[2] != 0.0f);
    }
  }
  return offUnit;
}


namespace {
#ifdef RTD_SIMD_AVX2
// The inverse of deinterleave8: eight pixels of channels c[0..stride) into `stride` (3 or 4)
// vectors of packed pixels. stride 3: each channel is permuted so that its values sit in the
// lanes they take in the three output vectors, then two blends per vector assemble them.
inline void interleave8(const __m256 c[4], int stride, __m256 out[4]) {
  if (stride == 3) {
    const __m256 r = _mm256_permutevar8x32_ps(c[0], _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    const __m256 g = _mm256_permutevar8x32_ps(c[1], _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2));
    const __m256 b = _mm256_permutevar8x32_ps(c[2], _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
    out[0] = _mm256_blend_ps(_mm256_blend_ps(r, g, 0b10010010), b, 0b00100100);
    out[1] = _mm256_blend_ps(_mm256_blend_ps(r, g, 0b00100100), b, 0b01001001);
    out[2] = _mm256_blend_ps(_mm256_blend_ps(r, g, 0b01001001), b, 0b10010010);
  } else {
    interleave4x8(c, out);
  }
}
#endif
}  // namespace

#ifdef RTD_SIMD_AVX512
namespace {
// Permutation indices for interleave16: float k of output vector kPart is channel at % kStride
// of pixel at / kStride, at = 16 kPart + k. kStep 0: from r || g (red's lane j as j, green's as
// 16 + j; 0 for the others); kStep 1: blue's lane j as 16 + j, else lane k of the first result.
template <int kStride, int kPart, int kStep> inline __m512i interleaveIndex() {
  alignas(64) int32_t i[16];
  for (int k = 0; k < 16; ++k) {
    const int at = 16 * kPart + k, pixel = at / kStride, channel = at % kStride;
    if (kStep == 0) i[k] = channel == 0 ? pixel : channel == 1 ? 16 + pixel : 0;
    else i[k] = channel == 2 ? 16 + pixel : k;
  }
  return _mm512_load_si512(i);
}
// Output vector kPart of 16 pixels of kStride (3, or 4 with alpha 1) floats from channels r, g, b.
template <int kStride, int kPart> inline vf interleave16(vf r, vf g, vf b) {
  const vf rg = _mm512_permutex2var_ps(r, interleaveIndex<kStride, kPart, 0>(), g);
  const vf rgb = _mm512_permutex2var_ps(rg, interleaveIndex<kStride, kPart, 1>(), b);
  if constexpr (kStride == 3) return rgb;
  else return _mm512_mask_mov_ps(rgb, 0x8888, splat(1.0f));  // every fourth float: alpha
}
// exportRow's 16-pixel loop (packed Float3 or Float4); returns the next x.
template <int kStride> int exportRow16(const float* const c[3], const float* const* e, float* row, int w, bool stream) {
  stream = stream && streamAligned(row);
  int x = 0;
  for (; x + 16 <= w; x += 16) {
    vf v[3];
    for (int k = 0; k < 3; ++k) v[k] = e ? load(c[k] + x) + load(e[k] + x) : load(c[k] + x);
    vf o[4];
    o[0] = interleave16<kStride, 0>(v[0], v[1], v[2]);
    o[1] = interleave16<kStride, 1>(v[0], v[1], v[2]);
    o[2] = interleave16<kStride, 2>(v[0], v[1], v[2]);
    if constexpr (kStride == 4) o[3] = interleave16<kStride, 3>(v[0], v[1], v[2]);
    for (int k = 0; k < kStride; ++k) {
      float* dst = row + size_t(x) * kStride + 16 * k;
      if (stream) streamStore(dst, o[k]);
      else store(dst, o[k]);
    }
  }
  if (stream) streamFence();
  return x;
}
}  // namespace
#endif

void exportRow(const float* const c[3], const float* const* e, const ImageView& out, int y, bool packed, bool stream) {
  const bool alpha = out.format == Format::Float4;
  int x = 0;
#ifdef RTD_SIMD_AVX512
  // Sixteen pixels at a time (the 8-lane loop below takes the rest of the row).
  if (packed) x = alpha ? exportRow16<4>(c, e, out.pixel<float>(0, y), out.width, stream)
                        : exportRow16<3>(c, e, out.pixel<float>(0, y), out.width, stream);
#endif
#ifdef RTD_SIMD_AVX2
  if (packed) {
    const int stride = alpha ? 4 : 3;
    float* row = out.pixel<float>(0, y);
    const bool nonTemporal = stream && reinterpret_cast<uintptr_t>(row) % 32 == 0;
    for (; x + 8 <= out.width; x += 8) {
      __m256 v[4], p[4];
      for (int k = 0; k < 3; ++k) {
        v[k] = _mm256_loadu_ps(c[k] + x);
        if (e) v[k] = _mm256_add_ps(v[k], _mm256_loadu_ps(e[k] + x));
      }
      v[3] = _mm256_set1_ps(1.0f);
      interleave8(v, stride, p);
      for (int k = 0; k < stride; ++k) {
        float* dst = row + size_t(x) * stride + 8 * k;
        if (nonTemporal) _mm256_stream_ps(dst, p[k]);
        else _mm256_storeu_ps(dst, p[k]);
      }
    }
    if (nonTemporal) streamFence();
  }
#endif
  for (; x < out.width; ++x) {
    float* p = out.pixel<float>(x, y);
    for (int k = 0; k < 3; ++k) p[k] = e ? c[k][x] + e[k][x] : c[k][x];
    if (alpha) p[3] = 1.0f;
  }
}

}  // namespace rtd::RTD_SIMD_NS
