// Reprojection: analytic camera motion, per-tap validity and renormalization, the 3x3
// fallback, and disocclusion.
#include <gtest/gtest.h>

#include <cmath>

#include "passes/reprojection.h"
#include "passes/temporal_accumulation.h"
#include "support/test_frames.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

// A camera translating by s along x shifts a point at view depth z by s * f / z pixels, f the
// focal length in pixels (h / (2 tan(fov/2))); nothing moves vertically.
TEST(Reprojection, KnownCameraTranslationGivesAnalyticPreviousPositions) {
  synthetic::Scene scene;
  scene.width = 96;
  scene.height = 54;
  scene.cameraSpeed = 0.05f;
  Frame prev = synthetic::makeFrame(scene, 3), cur = synthetic::makeFrame(scene, 4);
  // Remove the motion buffer: reprojection must then derive motion from the cameras.
  cur[Buffer::Motion] = Image();
  prev[Buffer::Motion] = Image();
  const FrameData p = test::toFrameData(prev), c = test::toFrameData(cur);
  Reprojection rp;
  reproject(c, &p, ReprojectionSettings{}, rp);

  const double focal = scene.height / (2.0 * std::tan(scene.verticalFov / 2.0));
  int checked = 0;
  for (int y = 0; y < scene.height; ++y)
    for (int x = 0; x < scene.width; ++x) {
      const float z = cur[Buffer::Depth].at(x, y);
      if (cur[Buffer::ObjectId].at(x, y) == 0) continue;  // sky
      const double expectedX = x + 0.5 + scene.cameraSpeed * focal / z;
      EXPECT_NEAR(rp.prevX(x, y), expectedX, 2e-3) << x << "," << y;
      EXPECT_NEAR(rp.prevY(x, y), y + 0.5, 2e-3) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, scene.width * scene.height / 2);

  // The motion buffer (computed by the scene independently) gives the same positions.
  Frame withMotion = synthetic::makeFrame(scene, 4);
  const FrameData cm = test::toFrameData(withMotion);
  Reprojection rm;
  reproject(cm, &p, ReprojectionSettings{}, rm);
  for (size_t i = 0; i < rp.prevX.size(); ++i)
    if (withMotion[Buffer::ObjectId].pixels[i] != 0) { ASSERT_NEAR(rm.prevX.data[i], rp.prevX.data[i], 2e-3); }
}

// Without motion vectors, a pixel without geometry (the sky) reprojects its view direction: a
// camera turning by d about +y (the synthetic scene's yaw) sees direction v = (sx, sy, -1) of
// the current camera at (cos d v.x + sin d v.z, v.y, -sin d v.x + cos d v.z) in the previous
// camera's space, whatever the sky pixels' world positions hold (0 here).
TEST(Reprojection, SkyWithoutMotionVectorsFollowsTheCameraRotation) {
  synthetic::Scene scene;
  scene.width = 96;
  scene.height = 54;
  scene.cameraSpeed = 0.03f;
  scene.cameraYawSpeed = 0.02f;
  Frame prev = synthetic::makeFrame(scene, 3), cur = synthetic::makeFrame(scene, 4);
  cur[Buffer::Motion] = Image();
  prev[Buffer::Motion] = Image();
  // The scene fills the view: its top 10 rows become sky (no normal, position 0).
  constexpr int kSkyRows = 10;
  for (Frame* f : {&prev, &cur})
    for (int y = 0; y < kSkyRows; ++y)
      for (int x = 0; x < scene.width; ++x)
        for (int k = 0; k < 3; ++k) (*f)[Buffer::Normal].at(x, y, k) = (*f)[Buffer::Position].at(x, y, k) = 0.0f;
  const FrameData p = test::toFrameData(prev), c = test::toFrameData(cur);
  Reprojection rp;
  reproject(c, &p, ReprojectionSettings{}, rp);
  const double t = std::tan(scene.verticalFov / 2.0), aspect = double(scene.width) / scene.height;
  const double d = scene.cameraYawSpeed;
  int checked = 0;
  for (int y = 0; y < scene.height; ++y)
    for (int x = 0; x < scene.width; ++x) {
      if (y >= kSkyRows) continue;  // geometry
      const double vx = (2.0 * (x + 0.5) / scene.width - 1.0) * t * aspect, vy = (1.0 - 2.0 * (y + 0.5) / scene.height) * t;
      const double qx = std::cos(d) * vx - std::sin(d), qz = -std::sin(d) * vx - std::cos(d);
      const double ex = (qx / -qz / (t * aspect) * 0.5 + 0.5) * scene.width, ey = (0.5 - vy / -qz / t * 0.5) * scene.height;
      EXPECT_NEAR(rp.prevX(x, y), ex, 2e-3) << x << "," << y;
      EXPECT_NEAR(rp.prevY(x, y), ey, 2e-3) << x << "," << y;
      ++checked;
    }
  EXPECT_EQ(checked, scene.width * kSkyRows);
}

TEST(Reprojection, StaticCameraMapsEveryPixelToItselfWithFullWeight) {
  const Frame f = test::flatFrame(13, 7, 0.5f);
  const FrameData d = test::toFrameData(f);
  Reprojection rp;
  reproject(d, &d, ReprojectionSettings{}, rp);
  Plane history(13, 7);
  for (size_t i = 0; i < history.size(); ++i) history.data[i] = float(i);
  for (size_t i = 0; i < rp.kind.size(); ++i) {
    ASSERT_EQ(rp.kind[i], Reprojection::Bilinear);
    EXPECT_FLOAT_EQ(rp.gather(history, i), float(i));  // exactly its own previous value
  }
}

// Motion (+0.5, +0.5) puts the history position on the corner of four pixels: equal bilinear
// weights. Making one tap fail the depth test leaves three taps of weight 1/3 each.
TEST(Reprojection, InvalidTapsGetZeroWeightAndTheRestAreRenormalized) {
  const int w = 8, h = 8;
  Frame prev = test::flatFrame(w, h, 0.0f, 2.0f), cur = test::flatFrame(w, h, 0.0f, 2.0f);
  for (int i = 0; i < w * h; ++i) {
    cur[Buffer::Motion].pixels[size_t(i) * 2 + 0] = 0.5f;
    cur[Buffer::Motion].pixels[size_t(i) * 2 + 1] = 0.5f;
  }
  // Pixel (3,3) reprojects to the corner between (3,3),(4,3),(3,4),(4,4) of the previous frame.
  prev[Buffer::Depth].at(4, 4) = 10.0f;  // fails the depth test
  const FrameData p = test::toFrameData(prev), c = test::toFrameData(cur);
  Reprojection rp;
  reproject(c, &p, ReprojectionSettings{}, rp);
  const size_t i = 3 * w + 3;
  ASSERT_EQ(rp.kind[i], Reprojection::Bilinear);
  EXPECT_NEAR(rp.weights[i][0], 1.0f / 3, 1e-6);
  EXPECT_NEAR(rp.weights[i][1], 1.0f / 3, 1e-6);
  EXPECT_NEAR(rp.weights[i][2], 1.0f / 3, 1e-6);
  EXPECT_EQ(rp.weights[i][3], 0.0f);

  Plane history(w, h);
  history(3, 3) = 3.0f;
  history(4, 3) = 6.0f;
  history(3, 4) = 9.0f;
  history(4, 4) = 1000.0f;  // the rejected tap must not leak in
  EXPECT_NEAR(rp.gather(history, i), (3.0f + 6.0f + 9.0f) / 3.0f, 1e-5);

  // All four taps fail a normal test: no bilinear history; the 3x3 fallback finds valid
  // neighbours around (4,4) and renormalizes the Gaussian kernel over them.
  Frame prev2 = prev;
  for (int y = 3; y <= 4; ++y)
    for (int x = 3; x <= 4; ++x) {
      prev2[Buffer::Depth].at(x, y) = 2.0f;
      prev2[Buffer::Normal].at(x, y, 2) = -1.0f;
    }
  const FrameData p2 = test::toFrameData(prev2);
  reproject(c, &p2, ReprojectionSettings{}, rp);
  ASSERT_EQ(rp.kind[i], Reprojection::Fallback3x3);
  // Centre is floor(3.5 + 0.5) = (4,4); valid taps: the 3x3 around it minus (3,3),(4,3),(3,4),(4,4).
  Plane h2(w, h);
  double sum = 0, wsum = 0;
  for (int t = 0; t < 9; ++t) {
    const int x = 4 + t % 3 - 1, y = 4 + t / 3 - 1;
    h2(x, y) = float(t + 1);
    if ((x == 3 || x == 4) && (y == 3 || y == 4)) continue;
    sum += kFallbackKernel3x3[t] * (t + 1);
    wsum += kFallbackKernel3x3[t];
  }
  EXPECT_NEAR(rp.gather(h2, i), sum / wsum, 1e-5);

  ReprojectionSettings noFallback;
  noFallback.fallback3x3 = false;
  reproject(c, &p2, noFallback, rp);
  EXPECT_EQ(rp.kind[i], Reprojection::None);
}

TEST(Reprojection, KernelOfTheFallbackIsTheHigginsonGaussian) {
  double sum = 0;
  for (float k : kFallbackKernel3x3) sum += k;
  EXPECT_NEAR(sum, 0.9997, 1e-4);  // Higginson Eq. 1.4 (sums to 0.9997 as printed)
  EXPECT_FLOAT_EQ(kFallbackKernel3x3[4], 0.1953f);
}

TEST(Reprojection, DisocclusionAndObjectChangeLeaveNoHistory) {
  const int w = 10, h = 6;
  Frame prev = test::flatFrame(w, h, 0.0f, 1.0f, 1.0f), cur = prev;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w / 2; ++x) cur[Buffer::ObjectId].at(x, y) = 2.0f;  // a new object on the left
  const FrameData p = test::toFrameData(prev), c = test::toFrameData(cur);
  Reprojection rp;
  reproject(c, &p, ReprojectionSettings{}, rp);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Left-half pixels next to the boundary may find old-object taps only through the 3x3
      // fallback if ids matched; they do not, so every left pixel is disoccluded.
      if (x < w / 2) { EXPECT_EQ(rp.kind[size_t(y) * w + x], Reprojection::None) << x; }
      else EXPECT_EQ(rp.kind[size_t(y) * w + x], Reprojection::Bilinear) << x;
    }
  // Motion pointing outside the image: no history.
  for (float& m : cur[Buffer::Motion].pixels) m = -100.0f;
  const FrameData c2 = test::toFrameData(cur);
  reproject(c2, &p, ReprojectionSettings{}, rp);
  EXPECT_EQ(rp.counts()[Reprojection::None], size_t(w * h));
}

// The history length the shared accumulator keeps: the reprojected previous length plus one,
// capped at 255 (BMFR's 8-bit counts), and 1 again where there is no history.
TEST(Reprojection, HistoryLengthFollowsReprojectionAndResets) {
  const Frame f = test::flatFrame(4, 4, 0.0f);
  const FrameData d = test::toFrameData(f);
  Reprojection rp, none;
  reproject(d, &d, ReprojectionSettings{}, rp);
  reproject(d, nullptr, ReprojectionSettings{}, none);
  const Plane3 color{Plane(4, 4, 0.5f), Plane(4, 4, 0.5f), Plane(4, 4, 0.5f)};
  TemporalAccumulator acc;
  acc.resize(4, 4);
  acc.run(none, color, 0.2f, 0.2f, 255);
  for (int k = 0; k < 6; ++k) acc.run(rp, color, 0.2f, 0.2f, 255);  // length 7
  acc.run(rp, color, 0.2f, 0.2f, 255);
  EXPECT_EQ(acc.historyLength()(1, 1), 8.0f);
  for (int k = 0; k < 300; ++k) acc.run(rp, color, 0.2f, 0.2f, 255);
  EXPECT_EQ(acc.historyLength()(1, 1), 255.0f);  // capped (8-bit counts)
  acc.run(none, color, 0.2f, 0.2f, 255);
  EXPECT_EQ(acc.historyLength()(1, 1), 1.0f);
}

}  // namespace
}  // namespace rtd

namespace rtd {
namespace {

// The reprojection's fast paths (eight pixels at a time, gathers) against a direct reading of
// the tap tests, on random features and a random motion field: every pixel whose bilinear
// footprint lies inside the previous frame and has a valid tap must get exactly the
// renormalized bilinear weights of its valid taps.
TEST(Reprojection, BilinearTapsMatchADirectEvaluationOfTheTests) {
  const int w = 67, h = 41;
  uint32_t state = 12345;
  auto rnd = [&] { state = state * 1664525u + 1013904223u; return float(state >> 8) / 16777216.0f; };
  auto frame = [&](bool withMotion) {
    FrameData f;
    f.width = w;
    f.height = h;
    auto planes = [&](Buffer b, int n) -> std::vector<Plane>& {
      f.buffers[int(b)].assign(n, Plane(w, h));
      return f.buffers[int(b)];
    };
    auto& z = planes(Buffer::Depth, 1);
    auto& nrm = planes(Buffer::Normal, 3);
    auto& id = planes(Buffer::ObjectId, 1);
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      z[0].data[i] = 2.0f + 0.3f * rnd();                   // depth test passes and fails
      const float a = 0.6f * rnd();                          // normals up to ~34 degrees apart
      nrm[0].data[i] = std::sin(a);
      nrm[1].data[i] = 0.0f;
      nrm[2].data[i] = rnd() < 0.05f ? 0.0f : std::cos(a);  // some background-like normals
      if (nrm[2].data[i] == 0.0f) nrm[0].data[i] = 0.0f;
      id[0].data[i] = rnd() < 0.9f ? 1.0f : 2.0f;
    }
    if (withMotion) {
      auto& m = planes(Buffer::Motion, 2);
      for (size_t i = 0; i < size_t(w) * h; ++i) { m[0].data[i] = 6.0f * rnd() - 3.0f; m[1].data[i] = 6.0f * rnd() - 3.0f; }
    }
    return f;
  };
  const FrameData prev = frame(false), cur = frame(true);
  const ReprojectionSettings s;
  Reprojection rp;
  reproject(cur, &prev, s, rp);

  const float* z = cur.plane(Buffer::Depth).ptr();
  int checked = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const float fx = x + cur.plane(Buffer::Motion, 0).data[i], fy = y + cur.plane(Buffer::Motion, 1).data[i];
      const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
      if (x0 < 0 || y0 < 0 || x0 >= w - 1 || y0 >= h - 1) continue;
      // Depth slope: per axis the smaller one-sided difference (clamped at the border).
      auto at = [&](int xx, int yy) { return z[size_t(std::clamp(yy, 0, h - 1)) * w + std::clamp(xx, 0, w - 1)]; };
      const float c = z[i];
      const float gx = std::min(std::abs(at(x - 1, y) - c), std::abs(at(x + 1, y) - c));
      const float gy = std::min(std::abs(at(x, y - 1) - c), std::abs(at(x, y + 1) - c));
      const double tol = double(s.depthTolerance) * c + double(s.depthGradientScale) * std::max(gx, gy);
      const float ax = fx - x0, ay = fy - y0;
      const double bw[4] = {(1.0 - ax) * (1.0 - ay), ax * (1.0 - ay), (1.0 - ax) * ay, double(ax) * ay};
      double wt[4], sum = 0;
      const float* n[3] = {cur.plane(Buffer::Normal, 0).ptr(), cur.plane(Buffer::Normal, 1).ptr(), cur.plane(Buffer::Normal, 2).ptr()};
      const float* np[3] = {prev.plane(Buffer::Normal, 0).ptr(), prev.plane(Buffer::Normal, 1).ptr(), prev.plane(Buffer::Normal, 2).ptr()};
      const bool background = n[2][i] == 0.0f;
      for (int t = 0; t < 4; ++t) {
        const size_t j = size_t(y0 + t / 2) * w + x0 + t % 2;
        const bool prevBackground = np[2][j] == 0.0f;
        const double dot = double(n[0][i]) * np[0][j] + double(n[2][i]) * np[2][j];
        const bool ok = std::abs(double(prev.plane(Buffer::Depth).data[j]) - c) <= tol &&
                        (background ? prevBackground : dot >= s.normalTolerance) &&
                        prev.plane(Buffer::ObjectId).data[j] == cur.plane(Buffer::ObjectId).data[i];
        wt[t] = ok ? bw[t] : 0.0;
        sum += wt[t];
      }
      if (sum <= 1e-4) continue;
      ASSERT_EQ(rp.kind[i], Reprojection::Bilinear) << x << "," << y;
      ASSERT_EQ(rp.base[i], y0 * w + x0) << x << "," << y;
      for (int t = 0; t < 4; ++t) EXPECT_NEAR(rp.weights[i][t], wt[t] / sum, 2e-5) << x << "," << y << " tap " << t;
      ++checked;
    }
  EXPECT_GT(checked, w * h / 2);
}

}  // namespace
}  // namespace rtd
