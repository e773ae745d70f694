// Random numbers for the path tracer: a pixel's samples are a hash-based Owen-scrambled Sobol
// (0,2)-sequence per pair of dimensions (Burley 2020, "Practical Hash-based Owen Scrambling"),
// driven only by (pixel seed, sample index, dimension). Nothing depends on thread scheduling,
// so frames are bit-identical for any thread count, and a pixel can be re-shaded from its seed.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

namespace rtd::render {

/// 32-bit integer hash (lowbias32, Chris Wellons' constants).
inline uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}
inline uint32_t hashCombine(uint32_t a, uint32_t b) { return hash32(a ^ (b + 0x9e3779b9U + (a << 6) + (a >> 2))); }

/// Laine-Karras style nested uniform scramble of a bit-reversed integer (Burley 2020, Sec. 3).
inline uint32_t laineKarras(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cU;
  x ^= x * 0xb82f1e52U;
  x ^= x * 0xc7afe638U;
  x ^= x * 0x8d22f6e6U;
  return x;
}
inline uint32_t reverseBits(uint32_t x) {
  x = __builtin_bswap32(x);  // bytes reversed; then the bits within each byte
  x = ((x >> 1) & 0x55555555U) | ((x & 0x55555555U) << 1);
  x = ((x >> 2) & 0x33333333U) | ((x & 0x33333333U) << 2);
  x = ((x >> 4) & 0x0F0F0F0FU) | ((x & 0x0F0F0F0FU) << 4);
  return x;
}
inline uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) {
  return reverseBits(laineKarras(reverseBits(x), seed));
}

/// Second Sobol dimension (the first is the bit reversal of the index): XOR of the generator
/// matrix's columns for the set bits, looked up a byte at a time.
uint32_t sobol1(uint32_t index);

inline float toUnitFloat(uint32_t x) { return float(x >> 8) * (1.0f / 16777216.0f); }  // [0, 1)

/// The samples of one pixel sample: next2D() walks through dimension pairs.
class Sampler {
 public:
  Sampler(uint32_t pixelSeed, uint32_t sampleIndex) : seed_(pixelSeed), index_(sampleIndex) {}
  /// Dimension pairs beyond this one are plain hashed random numbers: stratification matters
  /// for the first bounce, and later bounces would pay for the scrambling without benefit.
  static constexpr uint32_t kSobolPairs = 5;

  std::pair<float, float> next2D() {
    const uint32_t dimSeed = hashCombine(seed_, dimension_++);
    if (dimension_ > kSobolPairs) {
      const uint32_t h = hashCombine(dimSeed, index_);
      return {toUnitFloat(h), toUnitFloat(hash32(h ^ 0x9e3779b9U))};
    }
    // Shuffle the index (Owen-scramble it) so each dimension pair is decorrelated, then
    // scramble the two Sobol coordinates independently.
    const uint32_t i = nestedUniformScramble(index_, dimSeed);
    const uint32_t x = nestedUniformScramble(reverseBits(i), hash32(dimSeed ^ 0xa511e9b3U));
    const uint32_t y = nestedUniformScramble(sobol1(i), hash32(dimSeed ^ 0x63d83595U));
    return {toUnitFloat(x), toUnitFloat(y)};
  }
  float next1D() { return next2D().first; }

 private:
  uint32_t seed_, index_, dimension_ = 0;
};

/// A 64 x 64 blue-noise rank map (void-and-cluster, Ulichney 1993): every value 0..4095 once,
/// and any contiguous range of ranks is a well-spread point set.
const std::vector<uint16_t>& blueNoiseRanks();
constexpr int kBlueNoiseSize = 64;

}  // namespace rtd::render
