// TAA's own-surface clamp box (TaaSettings::taaOwnSurface, passes/taa_keys.h; issues 12 and 13):
// a ghost on one surface next to another is clamped to its own surface's box; a constant image
// stays a fixed point whatever the keys; all-equal keys are the plain box bit for bit; every CPU
// path gives the scalar path's result.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "core/frame_data.h"
#include "passes/taa.h"
#include "passes/taa_keys.h"
#include "support/cpu_paths.h"
#include "support/taa_frames.h"

namespace rtd {
namespace {

constexpr int kOwnSurfaceW = 24, kOwnSurfaceH = 13;

// Every pixel's history is its own pixel (still) or moved by a sub-pixel (dx, dy) (the history
// is resampled); every tap accepted.
Reprojection still() { return test::shiftedReprojection(kOwnSurfaceW, kOwnSurfaceH, 0.0f, 0.0f); }
Reprojection moving(float dx, float dy) { return test::shiftedReprojection(kOwnSurfaceW, kOwnSurfaceH, dx, dy); }
template <class F> Plane3 ownSurfaceImage(F f) { return test::imageOf(kOwnSurfaceW, kOwnSurfaceH, f); }
TaaSettings ownSurfaceSettings(bool own, TaaDomain d, TaaNeighbourhood shape = TaaNeighbourhood::box3x3) {
  TaaSettings s;
  s.taaAlpha = 0.1f;
  s.taaSubpixelAlpha = 0.0f;  // constant alpha: the subpixel motions here would otherwise take most history out
  s.taaDomain = d;
  s.taaNeighbourhood = shape;
  s.taaOwnSurface = own;
  return s;
}
uint32_t hash(uint32_t v) {
  v ^= v >> 16, v *= 0x7feb352du, v ^= v >> 15, v *= 0x846ca68bu, v ^= v >> 16;
  return v;
}
const char* name(TaaDomain d) { return d == TaaDomain::linear ? "linear" : "display"; }

// Left half surface A (radiance 1), right half surface B (radiance 0). Frame 1 sets A's history
// to 0.5 (a ghost) and B's to 0. Frame 2 is the two surfaces again: with the own-surface box
// every A pixel's box is {1} (A's pixels only), the ghost is clamped to 1 and the output is
// alpha * 1 + (1 - alpha) * 1 = 1; with the plain box, A's column next to B has a box [0, 1]
// that holds the ghost, so it stays (alpha + (1 - alpha) * 0.5 in the linear domain), while
// A's inner columns clamp it to 1 with either box. B's pixels (history 0 = B's value) are 0.
TEST(TaaOwnSurface, GhostNextToAnotherSurfaceIsClampedToItsOwnSurface) {
  const int split = kOwnSurfaceW / 2;
  PixelVector<uint32_t> keys(size_t(kOwnSurfaceW) * kOwnSurfaceH);
  for (int y = 0; y < kOwnSurfaceH; ++y)
    for (int x = 0; x < kOwnSurfaceW; ++x) keys[size_t(y) * kOwnSurfaceW + x] = x < split ? 7u : 9u;
  const Plane3 ghost = ownSurfaceImage([&](int x, int, int) { return x < split ? 0.5f : 0.0f; });
  const Plane3 two = ownSurfaceImage([&](int x, int, int) { return x < split ? 1.0f : 0.0f; });
  for (TaaDomain d : {TaaDomain::linear, TaaDomain::display})
    for (TaaNeighbourhood shape : {TaaNeighbourhood::box3x3, TaaNeighbourhood::boxCross})
      for (bool own : {true, false}) {
        Taa taa;
        taa.run(still(), ghost, ownSurfaceSettings(own, d, shape), &keys);
        const Plane3& out = taa.run(still(), two, ownSurfaceSettings(own, d, shape), &keys);
        for (int y = 0; y < kOwnSurfaceH; ++y)
          for (int x = 0; x < kOwnSurfaceW; ++x)
            for (int c = 0; c < 3; ++c) {
              const float v = out[c](x, y);
              const std::string at = std::string(name(d)) + (own ? " own" : " plain") + " x=" + std::to_string(x) +
                                     " y=" + std::to_string(y);
              if (x >= split) {
                EXPECT_EQ(v, 0.0f) << at;
              } else if (own || x < split - 1) {
                EXPECT_NEAR(v, 1.0f, 2e-6f) << at;
              } else {
                // The plain box keeps the ghost: in the linear domain 0.1 + 0.9 * 0.5 = 0.55; in
                // the display one the blend of the encodings (sqrt(1/2) and sqrt(1/3)) decoded.
                const double e = d == TaaDomain::linear ? 0.1 * 1.0 + 0.9 * 0.5
                                                        : 0.1 * std::sqrt(0.5) + 0.9 * std::sqrt(1.0 / 3.0);
                const double expected = d == TaaDomain::linear ? e : e * e / (1.0 - e * e);
                // The box-cross bounds at the border column: box [0, 1], cross [0, 1] (its
                // right tap is B): the same.
                EXPECT_NEAR(v, expected, 2e-6) << at;
                EXPECT_LT(v, 0.9f) << at;
              }
            }
      }
}

// A constant image stays a fixed point with random keys (every box over any subset of the
// neighbours is the constant), under sub-pixel motion, in both domains and both shapes.
TEST(TaaOwnSurface, ConstantImageIsAFixedPointWithRandomKeys) {
  PixelVector<uint32_t> keys(size_t(kOwnSurfaceW) * kOwnSurfaceH);
  for (size_t i = 0; i < keys.size(); ++i) keys[i] = hash(uint32_t(i)) % 3u;
  const Plane3 in = ownSurfaceImage([](int, int, int c) { return 0.2f + 0.3f * c; });
  for (TaaDomain d : {TaaDomain::linear, TaaDomain::display})
    for (TaaNeighbourhood shape : {TaaNeighbourhood::box3x3, TaaNeighbourhood::boxCross}) {
      Taa taa;
      Plane3 out;
      for (int f = 0; f < 4; ++f) out = taa.run(moving(0.37f, -0.21f), in, ownSurfaceSettings(true, d, shape), &keys);
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < out[c].size(); ++i) EXPECT_NEAR(out[c].data[i], in[c].data[i], 4e-6f) << name(d);
    }
}

// A textured, moving sequence: with all keys equal the option is the plain box bit for bit;
// with keys that differ (two surfaces and scattered single pixels) every CPU path gives the
// scalar (sse2) path's result within 2^-20 relative (the bilinear fetch's vector and scalar
// sums round differently) and differs from the plain box.
TEST(TaaOwnSurface, AllEqualKeysAreThePlainBoxAndEveryCpuPathAgrees) {
  PixelVector<uint32_t> equal(size_t(kOwnSurfaceW) * kOwnSurfaceH, 5u), mixed(size_t(kOwnSurfaceW) * kOwnSurfaceH);
  for (int y = 0; y < kOwnSurfaceH; ++y)
    for (int x = 0; x < kOwnSurfaceW; ++x) mixed[size_t(y) * kOwnSurfaceW + x] = (x + y / 2 < 13 ? 1u : 2u) | (hash(x * 97 + y) % 11 == 0 ? 0x80000000u : 0u);
  auto frame = [](int f) {
    return ownSurfaceImage([f](int x, int y, int c) {
      return 0.05f + 0.9f * float(hash(uint32_t((x + f) * 131 + y * 7 + c * 1013)) % 1000) / 1000.0f * (c == 1 ? 4.0f : 1.0f);
    });
  };
  auto runAll = [&](const TaaSettings& s, const PixelVector<uint32_t>* keys) {
    Taa taa;
    Plane3 out;
    for (int f = 0; f < 5; ++f) out = taa.run(moving(0.3f, 0.1f * f), frame(f), s, keys);
    return out;
  };
  for (TaaDomain d : {TaaDomain::linear, TaaDomain::display})
    for (TaaNeighbourhood shape : {TaaNeighbourhood::box3x3, TaaNeighbourhood::boxCross}) {
      const Plane3 plain = runAll(ownSurfaceSettings(false, d, shape), nullptr);
      const Plane3 same = runAll(ownSurfaceSettings(true, d, shape), &equal);
      const Plane3 off = runAll(ownSurfaceSettings(false, d, shape), &mixed);  // option off: keys not read
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(same[c].data, plain[c].data) << name(d);
        EXPECT_EQ(off[c].data, plain[c].data) << name(d);
      }
      Plane3 scalar;
      {
        test::ScopedCpuPath force(CpuPath::Sse2);
        scalar = runAll(ownSurfaceSettings(true, d, shape), &mixed);
      }
      double differs = 0;
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < scalar[c].size(); ++i) differs = std::max(differs, double(std::abs(scalar[c].data[i] - plain[c].data[i])));
      EXPECT_GT(differs, 0.01) << name(d);  // the keys change the result
      for (CpuPath path : test::supportedCpuPaths()) {
        test::ScopedCpuPath force(path);
        const Plane3 out = runAll(ownSurfaceSettings(true, d, shape), &mixed);
        for (int c = 0; c < 3; ++c)
          for (size_t i = 0; i < out[c].size(); ++i)
            // 2^-20 of (1 + x)^2: in the display domain the paths' encodes and decodes (vector
            // and scalar sqrt and division, and what each compiler contracts into FMAs) differ
            // by a few roundings of the encoded value, which the decode x = e^2 / (1 - e^2)
            // scales by about 2 (1 + x)^2 (clang's avx2 path: 3.8e-6 at x = 2.09).
            EXPECT_NEAR(out[c].data[i], scalar[c].data[i], 0x1p-20f * (1.0f + scalar[c].data[i]) * (1.0f + scalar[c].data[i]))
                << cpuPathName(path);
      }
    }
}

// The keys: object id * 4 + class, bit 31 at the emitters the filter leaves out; no keys
// without the buffers.
TEST(TaaOwnSurface, KeysTellObjectsClassesAndEmittersApart) {
  FrameData f;
  f.width = 4;
  f.height = 1;
  PixelVector<uint32_t> keys;
  EmitterSettings e;
  EXPECT_FALSE(taaSurfaceKeys(f, &e, nullptr, keys));
  auto add = [&](Buffer b, int n) {
    f.buffers[int(b)].assign(size_t(n), Plane{});
    for (Plane& p : f.buffers[int(b)]) p.resize(4, 1, 0.0f);
  };
  add(Buffer::ObjectId, 1);
  add(Buffer::Emission, 3);
  for (int x = 0; x < 4; ++x) f.plane(Buffer::ObjectId)(x, 0) = float(x < 2 ? 3 : 4);
  f.plane(Buffer::Emission, 0)(1, 0) = 10.0f;
  PixelVector<uint8_t> cls = {0, 0, 2, 1};
  e.excludeEmitters = true;
  ASSERT_TRUE(taaSurfaceKeys(f, &e, &cls, keys));
  EXPECT_EQ(keys[0], 12u);
  EXPECT_EQ(keys[1], 12u | kTaaEmitterKey);
  EXPECT_EQ(keys[2], 18u);
  EXPECT_EQ(keys[3], 17u);
  ASSERT_TRUE(taaSurfaceKeys(f, nullptr, nullptr, keys));  // a method that excludes no emitter (A-SVGF)
  EXPECT_EQ(keys[1], 12u);
}

}  // namespace
}  // namespace rtd
