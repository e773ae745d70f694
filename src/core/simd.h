// The per-path half of runtime dispatch (src/core/cpu_path.h). A hot-loop source file is
// named *_simd.cpp; CMake compiles it once per CPU path with RTD_SIMD_PATH = 0 (sse2), 1 (avx2)
// or 2 (avx512). The file includes everything it needs first, then this header, then writes
// its code inside `namespace rtd::RTD_SIMD_NS { ... }`:
//
// - the target pragma below applies from here to the end of the file, so only this file's own
//   functions (lambdas and templates defined here included) are compiled for the path; inline
//   functions and templates of the headers included before it keep the baseline target, so the
//   copies the linker keeps of them run on any x86-64 (an AVX2 copy of std::vector's code picked
//   for the whole library would crash an older CPU; scripts/check_isa.py verifies that no code
//   outside rtd::avx2 and rtd::avx512 uses AVX registers);
// - vf / vi are kLanes floats / ints (4 on sse2, 8 on avx2, 16 on avx512) with the helpers
//   below; RTD_SIMD_AVX2 / RTD_SIMD_AVX512 guard intrinsics (avx512 implies avx2).
//
// The dispatching side declares the entry points with RTD_SIMD_DECLARE and calls them with
// RTD_SIMD(name)(args...).
#pragma once
#ifndef RTD_SIMD_PATH
#error "core/simd.h is for *_simd.cpp files, which CMake compiles with RTD_SIMD_PATH set"
#endif
#include <cstdint>
#include <cstring>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define RTD_SIMD_X86 1
#endif

#include "core/flush.h"
#include "core/ivdep.h"

#if RTD_SIMD_PATH == 0
#define RTD_SIMD_NS sse2
#elif RTD_SIMD_PATH == 1
#define RTD_SIMD_NS avx2
#elif RTD_SIMD_PATH == 2
#define RTD_SIMD_NS avx512
#else
#error "RTD_SIMD_PATH must be 0, 1 or 2"
#endif

#if defined(RTD_SIMD_X86) && RTD_SIMD_PATH >= 1
#define RTD_SIMD_AVX2 1
#if RTD_SIMD_PATH == 2
#define RTD_SIMD_AVX512 1
#endif
// No arch= here: GCC does not inline a function across different arch settings, and the
// headers' helpers must inline into the kernels.
#if defined(__clang__)
#if RTD_SIMD_PATH == 2
#pragma clang attribute push(__attribute__((target("avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma,f16c,bmi,bmi2,lzcnt,popcnt"))), apply_to = function)
#else
#pragma clang attribute push(__attribute__((target("avx2,fma,f16c,bmi,bmi2,lzcnt,popcnt"))), apply_to = function)
#endif
#else
#if RTD_SIMD_PATH == 2
#pragma GCC target("avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma,f16c,bmi,bmi2,lzcnt,popcnt")
// GCC 12 warns (uninitialized, maybe-uninitialized) about the intrinsics' own
// _mm512_undefined_ps() (GCC bug 105593).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#else
#pragma GCC target("avx2,fma,f16c,bmi,bmi2,lzcnt,popcnt")
#endif
#endif
#endif


namespace rtd::RTD_SIMD_NS {

#if RTD_SIMD_PATH == 2 && defined(RTD_SIMD_X86)
constexpr int kLanes = 16;
#elif RTD_SIMD_PATH == 1 && defined(RTD_SIMD_X86)
constexpr int kLanes = 8;
#else
constexpr int kLanes = 4;
#endif

typedef float vf __attribute__((vector_size(4 * kLanes)));
typedef int32_t vi __attribute__((vector_size(4 * kLanes)));

inline vf load(const float* p) {
  vf v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(float* p, vf v) { std::memcpy(p, &v, sizeof v); }
/// Whether p is aligned for streamStore.
inline bool streamAligned(const float* p) { return reinterpret_cast<uintptr_t>(p) % sizeof(vf) == 0; }
/// A non-temporal store (p aligned to the vector's size): for planes written now and read next
/// frame, which would otherwise be read into the cache first (write-allocate) and push out what
/// the pass is still reading. Weakly ordered: streamFence() before other threads read them.
inline void streamStore(float* p, vf v) {
#if defined(RTD_SIMD_AVX512)
  _mm512_stream_ps(p, v);
#elif defined(RTD_SIMD_AVX2)
  _mm256_stream_ps(p, v);
#elif defined(RTD_SIMD_X86)
  _mm_stream_ps(p, v);
#else
  store(p, v);
#endif
}
inline void streamFence() {
#ifdef RTD_SIMD_X86
  _mm_sfence();
#endif
}
/// x in every lane (x - 0 is x for every x, -0 included, so GCC emits one broadcast; vf{} + x
/// would cost an addition first).
inline vf splat(float x) { return x - vf{}; }
inline vf asFloat(vi i) {
  vf f;
  std::memcpy(&f, &i, sizeof f);
  return f;
}
inline vi asInt(vf f) {
  vi i;
  std::memcpy(&i, &f, sizeof i);
  return i;
}
/// mask ? a : 0 (mask lanes all ones or all zeros), as bit operations.
inline vf keepIf(vi mask, vf a) { return asFloat(asInt(a) & mask); }
inline vf vabs(vf x) { return asFloat(asInt(x) & 0x7fffffff); }
// a > b ? a : b and a < b ? a : b: exactly what maxps and minps compute (the second operand
// where either is NaN or both are zero), so one instruction each; GCC, which does not know
// that, made the selects a compare and a blend.
inline vf vmax(vf a, vf b) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_max_ps(a, b);
#elif defined(RTD_SIMD_AVX2)
  return _mm256_max_ps(a, b);
#elif defined(RTD_SIMD_X86)
  return _mm_max_ps(a, b);
#else
  return a > b ? a : b;
#endif
}
inline vf vmin(vf a, vf b) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_min_ps(a, b);
#elif defined(RTD_SIMD_AVX2)
  return _mm256_min_ps(a, b);
#elif defined(RTD_SIMD_X86)
  return _mm_min_ps(a, b);
#else
  return a < b ? a : b;
#endif
}
/// 1/x to ~23 bits: hardware estimate plus one Newton step (cheaper than a division).
inline vf vrcp(vf x) {
#if defined(RTD_SIMD_AVX512)
  const vf r = _mm512_rcp14_ps(x);
#elif defined(RTD_SIMD_AVX2)
  const vf r = _mm256_rcp_ps(x);
#elif defined(RTD_SIMD_X86)
  const vf r = _mm_rcp_ps(x);
#else
  return 1.0f / x;
#endif
#ifdef RTD_SIMD_X86
  return r * (2.0f - x * r);
#endif
}
/// 1/sqrt(x) to ~23 bits: hardware estimate plus one Newton step, y (3 - x y^2) / 2 (a square
/// root and a division cost ~30 cycles of the divider on 16 lanes). x = 0 gives NaN, not inf.
inline vf vrsqrt(vf x) {
#if defined(RTD_SIMD_AVX512)
  const vf y = _mm512_rsqrt14_ps(x);
#elif defined(RTD_SIMD_AVX2)
  const vf y = _mm256_rsqrt_ps(x);
#elif defined(RTD_SIMD_X86)
  const vf y = _mm_rsqrt_ps(x);
#else
  vf y;
  for (int k = 0; k < kLanes; ++k) y[k] = 1.0f / __builtin_sqrtf(x[k]);
  return y;
#endif
#ifdef RTD_SIMD_X86
  return (0.5f * y) * (3.0f - x * y * y);
#endif
}
inline vf vsqrt(vf x) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_sqrt_ps(x);
#elif defined(RTD_SIMD_AVX2)
  return _mm256_sqrt_ps(x);
#elif defined(RTD_SIMD_X86)
  return _mm_sqrt_ps(x);
#else
  for (int k = 0; k < kLanes; ++k) x[k] = __builtin_sqrtf(x[k]);
  return x;
#endif
}
/// Round to the nearest integer (ties to even), for |x| < 2^22.
inline vf vround(vf x) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_roundscale_ps(x, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
#elif defined(RTD_SIMD_AVX2)
  return _mm256_round_ps(x, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
#else
  return (x + 12582912.0f) - 12582912.0f;  // 1.5 * 2^23
#endif
}
/// The largest integer <= x, for |x| < 2^22.
inline vf vfloor(vf x) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_roundscale_ps(x, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
#elif defined(RTD_SIMD_AVX2)
  return _mm256_floor_ps(x);
#else
  const vf r = vround(x);
  return r - keepIf(r > x, splat(1.0f));
#endif
}
/// base[index[k]] in lane k.
inline vf vgather(const float* base, vi index) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_i32gather_ps((__m512i)index, base, 4);
#elif defined(RTD_SIMD_AVX2)
  return _mm256_i32gather_ps(base, (__m256i)index, 4);
#else
  vf v;
  for (int k = 0; k < kLanes; ++k) v[k] = base[index[k]];
  return v;
#endif
}
/// Lane k of the 2 kLanes consecutive floats lo:hi (lo first) picked by index[k], each in
/// [0, 2 kLanes): a gather whose addresses lie within one such window, as two loads and one
/// permutation (two and a blend on avx2) where a gather costs a load per lane.
inline vf vpermute2(vf lo, vf hi, vi index) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_permutex2var_ps(lo, (__m512i)index, hi);
#elif defined(RTD_SIMD_AVX2)
  const __m256 a = _mm256_permutevar8x32_ps(lo, (__m256i)index), b = _mm256_permutevar8x32_ps(hi, (__m256i)index);
  return _mm256_blendv_ps(a, b, (__m256)asFloat(index > 7));
#else
  vf v;
  for (int k = 0; k < kLanes; ++k) v[k] = index[k] < kLanes ? lo[index[k]] : hi[index[k] - kLanes];
  return v;
#endif
}
/// Bit k set where lane k of a comparison's result is true.
inline uint32_t laneBits(vi mask) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_movepi32_mask((__m512i)mask);
#elif defined(RTD_SIMD_AVX2)
  return uint32_t(_mm256_movemask_ps((__m256)asFloat(mask)));
#elif defined(RTD_SIMD_X86)
  return uint32_t(_mm_movemask_ps((__m128)asFloat(mask)));
#else
  uint32_t bits = 0;
  for (int k = 0; k < kLanes; ++k) bits |= uint32_t(mask[k] != 0) << k;
  return bits;
#endif
}
/// Whether any lane of a comparison's result is true.
inline bool anyTrue(vi mask) { return laneBits(mask) != 0; }
/// Whether every lane of a comparison's result is true.
inline bool allTrue(vi mask) { return laneBits(mask) == (1u << kLanes) - 1u; }
#ifdef RTD_SIMD_AVX2
/// The smallest of eight int lanes (also for passes/bilinear8.h's eight-lane registers on avx512).
inline int minLane8(__m256i m) {
  m = _mm256_min_epi32(m, _mm256_permute2x128_si256(m, m, 1));
  m = _mm256_min_epi32(m, _mm256_shuffle_epi32(m, 0x4e));
  return _mm256_cvtsi256_si32(_mm256_min_epi32(m, _mm256_shuffle_epi32(m, 0xb1)));
}
#endif
/// The smallest and the largest lane (a reduction in registers: reading the lanes one by one
/// costs a store and kLanes loads).
inline int minLane(vi v) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_reduce_min_epi32((__m512i)v);
#elif defined(RTD_SIMD_AVX2)
  return minLane8((__m256i)v);
#else
  int r = v[0];
  for (int k = 1; k < kLanes; ++k) r = v[k] < r ? v[k] : r;
  return r;
#endif
}
inline int maxLane(vi v) { return -minLane(-v); }
/// k in lane k.
inline vi laneIndex() {
  vi v;
  for (int k = 0; k < kLanes; ++k) v[k] = k;
  return v;
}
/// c - a * b rounded once where the path has FMA (AVX2, AVX-512), whatever the compiler's
/// contraction rules: code whose small products must not underflow on their own (the weight
/// exponents of passes/atrous_simd.cpp) says so with this instead of relying on
/// -ffp-contract=fast, which clang applies only within a basic block (an instrumented or -O1
/// build splits them). SSE2 has no FMA: c - a * b.
inline vf vfnmadd(vf a, vf b, vf c) {
#if defined(RTD_SIMD_AVX512)
  return _mm512_fnmadd_ps(a, b, c);
#elif defined(RTD_SIMD_AVX2)
  return _mm256_fnmadd_ps(a, b, c);
#else
  return c - a * b;
#endif
}
/// Software prefetch distance of the passes that stream many planes at once, in floats (six
/// cache lines): the temporal passes read a dozen or more rows of frame-sized planes side by side
/// (the history's two tap rows of each plane, the current frame's, the outputs), more streams
/// than the hardware prefetchers follow (docs/performance.md, "Session 14").
constexpr int kPrefetchAhead = 96;
/// Asks for p[kPrefetchAhead] to be brought into the cache, for reading or (prefetchAheadForWrite)
/// for writing; a hint only, never a fault, whatever the address.
inline void prefetchAhead(const float* p) { __builtin_prefetch(p + kPrefetchAhead); }
inline void prefetchAheadForWrite(float* p) { __builtin_prefetch(p + kPrefetchAhead, 1); }
/// Magnitudes below kTiny to 0 (core/flush.h), for every stored value.
inline vf vflush(vf x) { return keepIf(vabs(x) >= kTiny, x); }
/// x * x, or 0 where |x| < sqrt(kTiny) (core/flush.h).
inline vf vsquareOrZero(vf x) { return keepIf(vabs(x) >= kTinyRoot, x * x); }

#ifdef RTD_SIMD_AVX2
// The same for code written with AVX2 intrinsics (eight lanes on both AVX paths).
inline __m256 flush8(__m256 v) {
  const __m256 magnitude = _mm256_and_ps(v, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
  return _mm256_and_ps(v, _mm256_cmp_ps(magnitude, _mm256_set1_ps(kTiny), _CMP_GE_OQ));
}
inline __m256 squareOrZero8(__m256 v) {
  const __m256 magnitude = _mm256_and_ps(v, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
  return _mm256_and_ps(_mm256_mul_ps(v, v), _mm256_cmp_ps(magnitude, _mm256_set1_ps(kTinyRoot), _CMP_GE_OQ));
}
/// Eight pixels of four floats each, p[m] holding pixels 2m and 2m + 1 (32 consecutive floats),
/// as one vector per channel (out[c] lane j: float c of pixel j): a 4 x 8 transpose.
inline void deinterleave4x8(const __m256 p[4], __m256 out[4]) {
  const __m256 a = _mm256_permute2f128_ps(p[0], p[2], 0x20), b = _mm256_permute2f128_ps(p[0], p[2], 0x31);  // 0|4, 1|5
  const __m256 c = _mm256_permute2f128_ps(p[1], p[3], 0x20), d = _mm256_permute2f128_ps(p[1], p[3], 0x31);  // 2|6, 3|7
  const __m256 t0 = _mm256_unpacklo_ps(a, b), t1 = _mm256_unpackhi_ps(a, b);
  const __m256 t2 = _mm256_unpacklo_ps(c, d), t3 = _mm256_unpackhi_ps(c, d);
  out[0] = _mm256_shuffle_ps(t0, t2, 0x44);
  out[1] = _mm256_shuffle_ps(t0, t2, 0xee);
  out[2] = _mm256_shuffle_ps(t1, t3, 0x44);
  out[3] = _mm256_shuffle_ps(t1, t3, 0xee);
}
/// The inverse of deinterleave4x8: four channel vectors of eight pixels as four vectors of
/// packed pixels (out[m]: pixels 2m and 2m + 1).
inline void interleave4x8(const __m256 c[4], __m256 out[4]) {
  const __m256 t0 = _mm256_unpacklo_ps(c[0], c[1]), t1 = _mm256_unpackhi_ps(c[0], c[1]);
  const __m256 t2 = _mm256_unpacklo_ps(c[2], c[3]), t3 = _mm256_unpackhi_ps(c[2], c[3]);
  // pixels 0|4, 1|5, 2|6, 3|7
  const __m256 p04 = _mm256_shuffle_ps(t0, t2, 0x44), p15 = _mm256_shuffle_ps(t0, t2, 0xee);
  const __m256 p26 = _mm256_shuffle_ps(t1, t3, 0x44), p37 = _mm256_shuffle_ps(t1, t3, 0xee);
  out[0] = _mm256_permute2f128_ps(p04, p15, 0x20);
  out[1] = _mm256_permute2f128_ps(p26, p37, 0x20);
  out[2] = _mm256_permute2f128_ps(p04, p15, 0x31);
  out[3] = _mm256_permute2f128_ps(p26, p37, 0x31);
}
#endif

}  // namespace rtd::RTD_SIMD_NS
