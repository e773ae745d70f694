// The bilinear history taps of eight consecutive pixels in AVX registers, for the passes that
// gather history eight pixels at a time (temporal accumulation, TAA; the reprojection's tap tests
// run kLanes wide in core/simd.h's types instead, passes/reprojection_simd.cpp). A header
// for *_simd.cpp files only (after core/simd.h): it exists on the avx2 and avx512 paths.
// Include passes/reprojection.h (and every other baseline header) before core/simd.h and this.
#pragma once
#include "core/simd.h"

#ifdef RTD_SIMD_AVX2
namespace rtd::RTD_SIMD_NS {

/// The bilinear taps of eight consecutive pixels in registers, for passes that gather history
/// eight pixels at a time. Where the eight footprints are consecutive (a locally uniform
/// integer motion, the common case) the taps are plain vector loads, otherwise gathers.
struct Bilinear8 {
  __m256i base;
  __m256 weight[4];
  int width;
  bool consecutive;

  /// Pixels i..i+7 if all are Bilinear; false otherwise (the caller takes them one by one).
  bool load(const Reprojection& rp, size_t i) {
    uint64_t kinds;
    std::memcpy(&kinds, rp.kind.data() + i, 8);
    if (kinds != 0x0101010101010101ull) return false;
    width = rp.width;
    base = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(rp.base.data() + i));
    consecutive = isConsecutive();
    // {w0, w1, w2, w3} per pixel to one register per tap.
    const float* wp = rp.weights[i].data();
    const __m256 packed[4] = {_mm256_loadu_ps(wp), _mm256_loadu_ps(wp + 8), _mm256_loadu_ps(wp + 16), _mm256_loadu_ps(wp + 24)};
    deinterleave4x8(packed, weight);
    return true;
  }

  /// The bilinear footprints of eight continuous previous positions (pixel units, centres at
  /// i + 0.5) in a width x height frame, with the plain bilinear weights; false unless all
  /// eight footprints lie inside the frame.
  bool footprint(const float* prevX, const float* prevY, int w, int h) {
    const __m256 fx = _mm256_sub_ps(_mm256_loadu_ps(prevX), _mm256_set1_ps(0.5f));
    const __m256 fy = _mm256_sub_ps(_mm256_loadu_ps(prevY), _mm256_set1_ps(0.5f));
    const __m256 flx = _mm256_floor_ps(fx), fly = _mm256_floor_ps(fy);
    const __m256 zero = _mm256_setzero_ps();
    const __m256 inside = _mm256_and_ps(
        _mm256_and_ps(_mm256_cmp_ps(flx, zero, _CMP_GE_OQ), _mm256_cmp_ps(flx, _mm256_set1_ps(float(w - 1)), _CMP_LT_OQ)),
        _mm256_and_ps(_mm256_cmp_ps(fly, zero, _CMP_GE_OQ), _mm256_cmp_ps(fly, _mm256_set1_ps(float(h - 1)), _CMP_LT_OQ)));
    if (_mm256_movemask_ps(inside) != 0xff) return false;
    const __m256 one = _mm256_set1_ps(1.0f);
    const __m256 ax = _mm256_sub_ps(fx, flx), ay = _mm256_sub_ps(fy, fly);
    const __m256 bx = _mm256_sub_ps(one, ax), by = _mm256_sub_ps(one, ay);
    weight[0] = _mm256_mul_ps(bx, by);
    weight[1] = _mm256_mul_ps(ax, by);
    weight[2] = _mm256_mul_ps(bx, ay);
    weight[3] = _mm256_mul_ps(ax, ay);
    width = w;
    base = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(fly), _mm256_set1_epi32(w)), _mm256_cvttps_epi32(flx));
    consecutive = isConsecutive();
    return true;
  }

  bool isConsecutive() const {
    const __m256i first = _mm256_set1_epi32(_mm256_extract_epi32(base, 0));
    return _mm256_movemask_epi8(_mm256_cmpeq_epi32(base, _mm256_add_epi32(first, _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)))) == -1;
  }

  /// Tap t (0: top left, 1: top right, 2: bottom left, 3: bottom right) of the eight pixels in
  /// plane h: one vector load where the footprints are consecutive, a gather otherwise.
  __m256 tap(const float* h, int t) const {
    const float* p = h + (t & 1) + (t >> 1) * width;
    return consecutive ? _mm256_loadu_ps(p + _mm256_extract_epi32(base, 0)) : _mm256_i32gather_ps(p, base, 4);
  }

  /// Prefetches both tap rows of plane h kPrefetchAhead floats beyond the first pixel's taps
  /// (where the following groups' taps lie when the motion is locally uniform).
  void prefetch(const float* h) const {
    const float* p = h + _mm256_extract_epi32(base, 0);
    prefetchAhead(p);
    prefetchAhead(p + width);
  }

  /// Prefetches the reprojection's record (load()'s kinds, bases and weights, the weights 16
  /// bytes a pixel, so two lines per eight pixels) of the eight pixels kPrefetchAhead pixels
  /// beyond pixel i: at the float planes' distance, as the record streams alongside them.
  static void prefetchRecord(const Reprojection& rp, size_t i) {
    const size_t j = i + kPrefetchAhead;
    const char* weights = reinterpret_cast<const char*>(rp.weights.data() + j);
    __builtin_prefetch(weights);
    __builtin_prefetch(weights + 64);
    __builtin_prefetch(rp.base.data() + j);
    __builtin_prefetch(rp.kind.data() + j);
  }

  /// The bilinear history of the eight pixels in plane h (the sum in Reprojection::gatherBilinear's order).
  __m256 gather(const float* h) const {
    __m256 v = _mm256_mul_ps(weight[0], tap(h, 0));
    v = _mm256_fmadd_ps(weight[1], tap(h, 1), v);
    v = _mm256_fmadd_ps(weight[2], tap(h, 2), v);
    return _mm256_fmadd_ps(weight[3], tap(h, 3), v);
  }
};

}  // namespace rtd::RTD_SIMD_NS
#endif
