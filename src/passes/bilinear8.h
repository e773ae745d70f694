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
/// integer motion, the common case) the taps are plain vector loads. Otherwise they usually
/// still start within 15 columns, on one row or on two neighbouring ones (a step in the motion
/// between the lanes; positions that round to either side of a texel centre line, as under a
/// static or panning camera): the taps are then permutations of a 16-float window of each row
/// (two loads and one permutation, three on avx2, where a gather costs a load per lane), picked
/// per lane between two rows in the second case. Gathers only where even that does not hold.
struct Bilinear8 {
  enum class Layout : uint8_t { consecutive, window, twoRowWindow, scattered };
  __m256i base;
  __m256 weight[4];
  int width;
  Layout layout;
  int anchor;          // window layouts: the windows' first element (row `anchor / width`)
  __m256i column[2];   // window layouts: taps t & 1 == 0 and 1, each lane's place in its window
  __m256 lower;        // twoRowWindow: the lanes whose footprint starts one row below the anchor's

  /// Pixels i..i+7 if all are Bilinear; false otherwise (the caller takes them one by one).
  /// `toGather`: false where only base and weight are read (no layout for gather()).
  bool load(const Reprojection& rp, size_t i, bool toGather = true) {
    uint64_t kinds;
    std::memcpy(&kinds, rp.kind.data() + i, 8);
    if (kinds != 0x0101010101010101ull) return false;
    width = rp.width;
    base = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(rp.base.data() + i));
    if (toGather) classify(size_t(rp.width) * rp.height);
    // {w0, w1, w2, w3} per pixel to one register per tap.
    const float* wp = rp.weights[i].data();
    const __m256 packed[4] = {_mm256_loadu_ps(wp), _mm256_loadu_ps(wp + 8), _mm256_loadu_ps(wp + 16), _mm256_loadu_ps(wp + 24)};
    deinterleave4x8(packed, weight);
    return true;
  }

  /// The bilinear footprints of eight continuous previous positions (pixel units, centres at
  /// i + 0.5) in a width x height frame, with the plain bilinear weights; false unless all
  /// eight footprints lie inside the frame.
  bool footprint(const float* prevX, const float* prevY, int w, int h, bool toGather = true) {
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
    if (toGather) classify(size_t(w) * h);
    return true;
  }

  /// The layout of the footprints in planes of `planeSize` floats.
  void classify(size_t planeSize) {
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const int first = _mm256_cvtsi256_si32(base);
    if (_mm256_movemask_epi8(_mm256_cmpeq_epi32(base, _mm256_add_epi32(_mm256_set1_epi32(first), lane))) == -1) {
      layout = Layout::consecutive;
      return;
    }
    // Lanes more than half a row past the top-most footprint start a row lower: their place in
    // the window row above is base - width. (Which lanes are called lower does not change where
    // a tap is read, window row + column = base + tap offset, only whether the window fits.)
    const __m256i lowerLanes = _mm256_cmpgt_epi32(_mm256_sub_epi32(base, _mm256_set1_epi32(minLane8(base))), _mm256_set1_epi32(width / 2));
    const __m256i upper = _mm256_sub_epi32(base, _mm256_and_si256(lowerLanes, _mm256_set1_epi32(width)));
    anchor = minLane8(upper);
    column[0] = _mm256_sub_epi32(upper, _mm256_set1_epi32(anchor));
    column[1] = _mm256_add_epi32(column[0], _mm256_set1_epi32(1));
    const bool twoRows = _mm256_movemask_epi8(lowerLanes) != 0;
    // Each lane's two columns in the window, and the windows' last vector inside the plane.
    const bool fits = _mm256_movemask_epi8(_mm256_cmpgt_epi32(column[1], _mm256_set1_epi32(15))) == 0 &&
                      size_t(anchor) + size_t(twoRows ? 2 : 1) * width + 16 <= planeSize;
    lower = _mm256_castsi256_ps(lowerLanes);
    layout = !fits ? Layout::scattered : twoRows ? Layout::twoRowWindow : Layout::window;
  }

  /// Lane k of the 16 floats lo:hi picked by index[k] in [0, 16).
  static __m256 permute16(__m256 lo, __m256 hi, __m256i index) {
#ifdef RTD_SIMD_AVX512
    return _mm256_permutex2var_ps(lo, index, hi);
#else
    return _mm256_blendv_ps(_mm256_permutevar8x32_ps(lo, index), _mm256_permutevar8x32_ps(hi, index),
                            _mm256_castsi256_ps(_mm256_cmpgt_epi32(index, _mm256_set1_epi32(7))));
#endif
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

  /// The bilinear history of the eight pixels in plane h (the sum in Reprojection::gatherBilinear's
  /// order). Taps t: 0 top left, 1 top right, 2 bottom left, 3 bottom right.
  __m256 gather(const float* h) const {
    __m256 tap[4];
    if (layout == Layout::consecutive) {
      const float* p = h + _mm256_cvtsi256_si32(base);
      tap[0] = _mm256_loadu_ps(p), tap[1] = _mm256_loadu_ps(p + 1);
      tap[2] = _mm256_loadu_ps(p + width), tap[3] = _mm256_loadu_ps(p + width + 1);
    } else if (layout == Layout::scattered) {
      for (int t = 0; t < 4; ++t) tap[t] = _mm256_i32gather_ps(h + (t & 1) + (t >> 1) * width, base, 4);
    } else {
      const float* p = h + anchor;
      const __m256 lo0 = _mm256_loadu_ps(p), hi0 = _mm256_loadu_ps(p + 8);
      const __m256 lo1 = _mm256_loadu_ps(p + width), hi1 = _mm256_loadu_ps(p + width + 8);
      for (int t = 0; t < 4; ++t) tap[t] = t < 2 ? permute16(lo0, hi0, column[t & 1]) : permute16(lo1, hi1, column[t & 1]);
      if (layout == Layout::twoRowWindow) {  // the lower lanes: one window row further down
        const __m256 lo2 = _mm256_loadu_ps(p + 2 * width), hi2 = _mm256_loadu_ps(p + 2 * width + 8);
        for (int t = 0; t < 4; ++t)
          tap[t] = _mm256_blendv_ps(tap[t], t < 2 ? tap[t + 2] : permute16(lo2, hi2, column[t & 1]), lower);
      }
    }
    __m256 v = _mm256_mul_ps(weight[0], tap[0]);
    v = _mm256_fmadd_ps(weight[1], tap[1], v);
    v = _mm256_fmadd_ps(weight[2], tap[2], v);
    return _mm256_fmadd_ps(weight[3], tap[3], v);
  }
};

}  // namespace rtd::RTD_SIMD_NS
#endif
