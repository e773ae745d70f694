// The shared TAA pass (Karis 2014): fixed points, exact reprojection of a shifted image, the
// YCoCg neighbourhood clamp and the blend, on hand-computed values.
#include <gtest/gtest.h>

#include <cmath>

#include "passes/taa.h"

namespace rtd {
namespace {

constexpr int kW = 23, kH = 17;

// Every pixel's history comes from (x + shiftX, y): prev = p + 0.5 + shift.
Reprojection shifted(float shiftX) {
  Reprojection rp;
  rp.resize(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) { rp.prevX(x, y) = x + 0.5f + shiftX; rp.prevY(x, y) = y + 0.5f; }
  return rp;
}

template <class F> Plane3 image(F f) {
  Plane3 p;
  resize(p, kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c) p[c](x, y) = f(x, y, c);
  return p;
}

TEST(Taa, ConstantImageIsAFixedPoint) {
  const Plane3 in = image([](int, int, int c) { return 0.2f + 0.3f * c; });
  Taa taa;
  Plane3 out;
  const Reprojection rp = shifted(0.37f);
  for (int f = 0; f < 4; ++f) out = taa.run(rp, in, 0.1f);
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < out[c].size(); ++i) EXPECT_NEAR(out[c].data[i], in[c].data[i], 1e-6f);
}

// An image moving one pixel left per frame, with motion saying so: the history of every
// pixel is exactly its current value, so the output is the input. Without the motion the
// history is the neighbour's value and the output differs.
TEST(Taa, ExactMotionReproducesAMovingImage) {
  auto frame = [](int t) {
    return image([t](int x, int y, int c) { return 0.5f + 0.4f * std::sin(0.9f * (x + t) + 0.3f * y + c); });
  };
  Taa taa;
  Plane3 out;
  out = taa.run(shifted(1.0f), frame(0), 0.1f);
  const Plane3 cur = frame(1);
  out = taa.run(shifted(1.0f), cur, 0.1f);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW - 1; ++x)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[c](x, y), cur[c](x, y), 2e-6f) << x << "," << y;

  Taa still;
  out = still.run(shifted(0.0f), frame(0), 0.1f);
  out = still.run(shifted(0.0f), cur, 0.1f);
  double err = 0;
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < out[c].size(); ++i) err = std::max(err, double(std::abs(out[c].data[i] - cur[c].data[i])));
  EXPECT_GT(err, 0.05);
}

// A white history over a black frame lies outside the frame's 3x3 box ({0}): it is clamped to
// black, so nothing ghosts.
TEST(Taa, ClampRejectsHistoryOutsideTheNeighbourhood) {
  Taa taa;
  Plane3 out;
  out = taa.run(shifted(0.0f), image([](int, int, int) { return 1.0f; }), 0.1f);
  out = taa.run(shifted(0.0f), image([](int, int, int) { return 0.0f; }), 0.1f);
  for (int c = 0; c < 3; ++c)
    for (float v : out[c].data) EXPECT_EQ(v, 0.0f);
}

// Grey history 0.5 inside the box of a grey 0.4/0.6 checkerboard: not clamped, so the output
// is alpha * current + (1 - alpha) * 0.5 exactly (grey has Co = Cg = 0).
TEST(Taa, HistoryInsideTheBoxIsBlendedWithAlpha) {
  Taa taa;
  Plane3 out;
  const float alpha = 0.25f;
  out = taa.run(shifted(0.0f), image([](int, int, int) { return 0.5f; }), alpha);
  const Plane3 checker = image([](int x, int y, int) { return (x + y) % 2 ? 0.6f : 0.4f; });
  out = taa.run(shifted(0.0f), checker, alpha);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(out[c](x, y), alpha * checker[c](x, y) + (1 - alpha) * 0.5f, 1e-6f) << x << "," << y;
}

// A pixel whose reprojected centre is outside the previous frame keeps its current colour.
TEST(Taa, PixelsWithoutHistoryKeepTheCurrentColour) {
  Taa taa;
  Plane3 out;
  out = taa.run(shifted(0.0f), image([](int, int, int) { return 0.9f; }), 0.1f);
  const Plane3 cur = image([](int x, int, int c) { return 0.1f * c + 0.01f * x; });
  out = taa.run(shifted(-float(kW) - 2.0f), cur, 0.1f);
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < out[c].size(); ++i) EXPECT_NEAR(out[c].data[i], cur[c].data[i], 1e-6f);
}

}  // namespace
}  // namespace rtd
