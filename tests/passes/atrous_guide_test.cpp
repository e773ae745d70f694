// The a-trous guide's depth gradient (AtrousGuide::build, passes/atrous.h), which scales w_z's
// denominator sigma_z |grad z . (p - q)|: per axis the one-sided difference of smaller
// magnitude, so that a depth edge next to a pixel does not widen its own slope; at the frame's
// border the one difference there is; a slope steeper than maxDepthSlope |z| is made huge.
// Also the padded planes' row layout (PaddedPlane) that the a-trous taps walk.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/plane.h"
#include "passes/atrous.h"

namespace rtd {
namespace {

struct Depth {
  Plane z;
  std::vector<Plane> n;
};

template <class F> Depth depthOf(int w, int h, F f) {
  Depth d;
  d.z.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) d.z(x, y) = f(x, y);
  d.n.assign(3, Plane());
  for (int c = 0; c < 3; ++c) d.n[c].resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) d.n[2](x, y) = 1.0f;
  return d;
}

AtrousGuide guideOf(const Depth& d, float maxDepthSlope = 0.0f) {
  AtrousGuide g;
  g.resize(d.z.width, d.z.height, 4);
  g.build(d.z, d.n, nullptr, maxDepthSlope);
  return g;
}

// A ramp of slope 0.01 along x and 0.02 along y with a step of 3 between columns 5 and 6 and
// between rows 3 and 4: on either side of each step the difference away from it is the ramp's,
// so the gradient is the ramp's at every pixel, border pixels included (odd sizes, so that the
// interior loops end off any vector width).
TEST(AtrousGuide, DepthGradientIgnoresAnEdgeNextToThePixel) {
  const int w = 13, h = 9;
  const Depth d = depthOf(w, h, [](int x, int y) {
    return 0.5f + 0.01f * float(x) + 0.02f * float(y) + (x > 5 ? 3.0f : 0.0f) + (y > 3 ? 3.0f : 0.0f);
  });
  const AtrousGuide g = guideOf(d);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      EXPECT_NEAR(g.gradX.at(x, y), 0.01f, 2e-6f) << x << ", " << y;
      EXPECT_NEAR(g.gradY.at(x, y), 0.02f, 2e-6f) << x << ", " << y;
    }
}

// The smaller magnitude, whatever the signs: a V (x) and a roof (y).
TEST(AtrousGuide, DepthGradientTakesTheSmallerMagnitudeOfTheTwoSides) {
  const int w = 9, h = 7;
  const Depth d = depthOf(w, h, [](int x, int y) {
    const float vx = x <= 4 ? -0.5f * float(x) : -2.0f + 0.25f * float(x - 4);  // slopes -0.5, then +0.25
    const float ry = y <= 3 ? 0.1f * float(y) : 0.3f - 0.4f * float(y - 3);     // slopes +0.1, then -0.4
    return 10.0f + vx + ry;
  });
  const AtrousGuide g = guideOf(d);
  for (int y = 0; y < h; ++y) {
    EXPECT_NEAR(g.gradX.at(0, y), -0.5f, 1e-5f);
    EXPECT_NEAR(g.gradX.at(3, y), -0.5f, 1e-5f);
    EXPECT_NEAR(g.gradX.at(4, y), 0.25f, 1e-5f);  // |-0.5| vs |0.25|
    EXPECT_NEAR(g.gradX.at(8, y), 0.25f, 1e-5f);
  }
  for (int x = 0; x < w; ++x) {
    EXPECT_NEAR(g.gradY.at(x, 0), 0.1f, 1e-5f);
    EXPECT_NEAR(g.gradY.at(x, 3), 0.1f, 1e-5f);  // |0.1| vs |-0.4|
    EXPECT_NEAR(g.gradY.at(x, 4), -0.4f, 1e-5f);
    EXPECT_NEAR(g.gradY.at(x, 6), -0.4f, 1e-5f);
  }
}

// One row or one column: no difference along it, the gradient there is 0.
TEST(AtrousGuide, DepthGradientOfASingleRowOrColumnIsZeroAlongIt) {
  const AtrousGuide row = guideOf(depthOf(6, 1, [](int x, int) { return 1.0f + 0.5f * float(x); }));
  const AtrousGuide column = guideOf(depthOf(1, 6, [](int, int y) { return 1.0f + 0.5f * float(y); }));
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(row.gradX.at(i, 0), 0.5f);
    EXPECT_EQ(row.gradY.at(i, 0), 0.0f);
    EXPECT_EQ(column.gradX.at(0, i), 0.0f);
    EXPECT_EQ(column.gradY.at(0, i), 0.5f);
  }
}

// z = 1 + 2x: |grad z| = 2 exceeds maxDepthSlope |z| = (1 + 2x) / 2 where x < 1.5. There the
// gradient is the huge (2^32, 2^32 (sqrt 2 - 1)) that makes w_z 1; elsewhere it stays.
TEST(AtrousGuide, SlopesSteeperThanMaxDepthSlopeBecomeHuge) {
  const int w = 11, h = 3;
  const AtrousGuide g = guideOf(depthOf(w, h, [](int x, int) { return 1.0f + 2.0f * float(x); }), 0.5f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (x < 2) {
        EXPECT_EQ(g.gradX.at(x, y), 0x1p32f) << x;
        EXPECT_EQ(g.gradY.at(x, y), 0x1p32f * 0.41421356f) << x;
      } else {
        EXPECT_EQ(g.gradX.at(x, y), 2.0f) << x;
        EXPECT_EQ(g.gradY.at(x, y), 0.0f) << x;
      }
    }
}

// PaddedPlane's layout: rows a multiple of the widest vector (16 floats, one 64-byte line) apart
// and an odd count of lines, so that the five rows of an a-trous window at step 2^k (k <= 4)
// fall into at least four different sets of a 4 KiB-periodic L1 cache (the step-16 level's rows
// all shared one set at 1280 px before); the border stays zero and pixels do not overlap.
TEST(PaddedPlane, RowsAreAnOddCountOfLinesApartAndPixelsKeepTheirPlaces) {
  for (int w : {1, 15, 16, 320, 1280, 1920, 3840})
    for (int padding : {4, 32}) {
      PaddedPlane p;
      const int h = 5;
      p.resize(w, h, padding);
      SCOPED_TRACE(::testing::Message() << "width " << w << ", padding " << padding);
      constexpr int a = PaddedPlane::kAlignment;
      EXPECT_GE(p.pad, padding);
      EXPECT_EQ(p.pad % a, 0);
      EXPECT_EQ(p.stride % a, 0);
      EXPECT_EQ(p.stride / a % 2, 1);
      EXPECT_GE(p.stride, w + 2 * p.pad);
      for (int step : {1, 2, 4, 8, 16}) {
        bool set[64] = {};
        int distinct = 0;
        for (int k = 0; k < 5; ++k) {
          const size_t line = size_t(k) * step * p.stride * sizeof(float) / 64;
          distinct += !set[line % 64];
          set[line % 64] = true;
        }
        EXPECT_GE(distinct, 4) << "step " << step;
      }
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) p.at(x, y) = float(1 + y * w + x);
      size_t nonZero = 0;
      for (float v : p.data) nonZero += v != 0.0f;
      EXPECT_EQ(nonZero, size_t(w) * h);  // nothing written to the border or over another pixel
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) ASSERT_EQ(p.row(y)[x], float(1 + y * w + x));
    }
}

}  // namespace
}  // namespace rtd
