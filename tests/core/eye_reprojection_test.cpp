// The shared eye-reprojection pass (Gersthofer Sec. 3.4.2): a fronto-parallel plane seen by
// two parallel cameras lands on the analytically expected pixel of the other eye; occluded
// points, other meshes, other normals and taps without data are rejected; identical eyes
// exchange their light exactly; sharing halves the variance of independent noise.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "passes/eye_reprojection.h"

namespace rtd {
namespace {

constexpr int W = 64, H = 48;
constexpr float kFovY = 60.0f * 3.14159265358979f / 180.0f;
constexpr float kAspect = float(W) / float(H);
const float kFocal = 1.0f / std::tan(0.5f * kFovY);

// A camera at (ex, 0, 0) looking down -Z with an OpenGL perspective projection.
Camera camera(float ex) {
  Camera c;
  c.worldToCamera = {1, 0, 0, -ex, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const float n = 0.01f, f = 1000.0f;
  c.projection = {kFocal / kAspect, 0, 0, 0, 0, kFocal, 0, 0, 0, 0, (n + f) / (n - f), 2 * n * f / (n - f), 0, 0, -1, 0};
  c.valid = true;
  return c;
}

// The eye at ex looking at the plane z = -depth (normal +z, object 1): features of every pixel.
FrameData planeFrame(float ex, float depth) {
  FrameData f;
  f.width = W;
  f.height = H;
  f.camera = camera(ex);
  auto planes = [&](Buffer b, int n) { f.buffers[int(b)] = std::vector<Plane>(size_t(n), Plane(W, H)); };
  planes(Buffer::Position, 3);
  planes(Buffer::Normal, 3);
  planes(Buffer::Depth, 1);
  planes(Buffer::ObjectId, 1);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float ndx = (x + 0.5f) / W * 2 - 1, ndy = 1 - (y + 0.5f) / H * 2;
      f.plane(Buffer::Position, 0)(x, y) = ex + ndx * depth * kAspect / kFocal;
      f.plane(Buffer::Position, 1)(x, y) = ndy * depth / kFocal;
      f.plane(Buffer::Position, 2)(x, y) = -depth;
      f.plane(Buffer::Normal, 2)(x, y) = 1.0f;
      f.plane(Buffer::Depth)(x, y) = depth;
      f.plane(Buffer::ObjectId)(x, y) = 1.0f;
    }
  return f;
}

// R = x + 0.5, G = y + 0.5 (the pixel centre), B = 1: bilinear gathers return the position.
Plane3 coordinates() {
  Plane3 p;
  for (auto& c : p) c.resize(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      p[0](x, y) = x + 0.5f;
      p[1](x, y) = y + 0.5f;
      p[2](x, y) = 1.0f;
    }
  return p;
}

Plane3 constant(float v) {
  Plane3 p;
  for (auto& c : p) c.resize(W, H, v);
  return p;
}

TEST(EyeReprojection, FrontoParallelPlaneLandsOnTheAnalyticDisparity) {
  const float baseline = 0.1f, depth = 2.0f;
  const FrameData left = planeFrame(-0.5f * baseline, depth), right = planeFrame(0.5f * baseline, depth);
  // Parallel cameras: a point at depth Z moves by b f W / (2 a Z) pixels to the left.
  const float disparity = baseline * kFocal * W / (2.0f * kAspect * depth);
  ASSERT_GT(disparity - std::floor(disparity), 0.05f);  // a fractional shift: both taps weigh
  const EyeGuide gl = EyeGuide::of(left), gr = EyeGuide::of(right);
  const ReprojectionSettings s;
  const Plane3 target = constant(0.0f), source = coordinates();
  Plane3 out = constant(-1.0f);
  Plane moved(W, H);
  eyeReproject(gl, gr, s, 1.0f, target, source, out, &moved);
  int checked = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float expected = x + 0.5f - disparity;  // landing point in the right eye, pixel units
      const bool inside = expected - 0.5f >= 0.0f && expected - 0.5f <= W - 1;
      if (!inside) continue;
      ++checked;
      ASSERT_EQ(moved(x, y), 1.0f) << x << "," << y;
      EXPECT_NEAR(out[0](x, y), expected, 2e-3f) << x << "," << y;
      EXPECT_NEAR(out[1](x, y), y + 0.5f, 2e-3f) << x << "," << y;
      // The taps are the pixels around the landing point, their weights its bilinear ones:
      // their weighted mean is the landing point (tap centres at integers here).
      const EyeTaps t = eyeTaps(gl, gr, s, size_t(y) * W + x);
      ASSERT_GE(t.count, 1);
      double mx = 0, my = 0;
      for (int k = 0; k < t.count; ++k) {
        EXPECT_LE(std::abs(t.index[k] % W - (expected - 0.5f)), 1.0f);
        EXPECT_LE(std::abs(t.index[k] / W - y), 1);
        mx += t.weight[k] * (t.index[k] % W);
        my += t.weight[k] * (t.index[k] / W);
      }
      EXPECT_NEAR(mx, expected - 0.5f, 2e-3);
      EXPECT_NEAR(my, y, 2e-3);
    }
  EXPECT_GT(checked, W * H * 9 / 10);
  // The other direction: the left eye sees the right eye's pixel shifted to the right.
  eyeReproject(gr, gl, s, 1.0f, target, source, out);
  EXPECT_NEAR(out[0](20, 10), 20.5f + disparity, 2e-3f);
}

TEST(EyeReprojection, OccludedOtherMeshOtherNormalAndEmptyTapsAreRejected) {
  const float baseline = 0.1f, depth = 2.0f;
  const FrameData left = planeFrame(-0.5f * baseline, depth);
  FrameData right = planeFrame(0.5f * baseline, depth);
  Plane valid(W, H, 1.0f);
  // Four vertical bands of the right eye, each failing one test:
  for (int y = 0; y < H; ++y) {
    for (int x = 10; x < 16; ++x) right.plane(Buffer::Depth)(x, y) = 1.0f;      // an occluder of the same mesh in front
    for (int x = 22; x < 28; ++x) right.plane(Buffer::ObjectId)(x, y) = 2.0f;   // another mesh at the same depth
    for (int x = 34; x < 40; ++x) {                                             // a surface turned by 60 degrees
      right.plane(Buffer::Normal, 0)(x, y) = std::sin(1.047f);
      right.plane(Buffer::Normal, 2)(x, y) = std::cos(1.047f);
    }
    for (int x = 46; x < 52; ++x) valid(x, y) = 0.0f;                            // no light there yet
  }
  EyeGuide gl = EyeGuide::of(left), gr = EyeGuide::of(right);
  gr.valid = &valid;
  const ReprojectionSettings s;
  const float disparity = baseline * kFocal * W / (2.0f * kAspect * depth);
  const Plane3 target = constant(7.0f), source = constant(1.0f);
  Plane3 out = constant(0.0f);
  Plane moved(W, H);
  eyeReproject(gl, gr, s, 0.5f, target, source, out, &moved);
  int rejected = 0, accepted = 0;
  for (int x = 0; x < W; ++x) {
    const float land = x + 0.5f - disparity - 0.5f;  // continuous tap coordinate in the right eye
    const int x0 = int(std::floor(land));
    auto inBand = [&](int a, int b) { return x0 + 1 >= a && x0 < b; };  // a tap of the footprint in [a, b)
    const bool bad = inBand(10, 16) || inBand(22, 28) || inBand(34, 40) || inBand(46, 52);
    const bool fullyBad = (x0 >= 10 && x0 + 1 < 16) || (x0 >= 22 && x0 + 1 < 28) || (x0 >= 34 && x0 + 1 < 40) ||
                          (x0 >= 46 && x0 + 1 < 52);
    if (land < 0 || land > W - 1) continue;
    for (int y = 0; y < H; ++y) {
      if (fullyBad) {
        EXPECT_EQ(moved(x, y), 0.0f) << x;
        EXPECT_EQ(out[0](x, y), 7.0f) << x;  // unchanged
        ++rejected;
      } else if (!bad) {
        EXPECT_EQ(moved(x, y), 1.0f) << x;
        EXPECT_NEAR(out[0](x, y), 4.0f, 1e-5f) << x;  // 0.5 * 7 + 0.5 * 1
        ++accepted;
      }
    }
  }
  EXPECT_GT(rejected, 4 * 4 * H);
  EXPECT_GT(accepted, 30 * H);
  // Without the depth test the same-mesh occluder is not noticed.
  ReprojectionSettings noDepth;
  noDepth.testDepth = false;
  const int xOcc = int(std::lround(12.5f + disparity));  // lands in the middle of the occluder band
  eyeReproject(gl, gr, noDepth, 0.5f, target, source, out, &moved);
  EXPECT_EQ(moved(xOcc, 5), 1.0f);
  eyeReproject(gl, gr, s, 0.5f, target, source, out, &moved);
  EXPECT_EQ(moved(xOcc, 5), 0.0f);
}

TEST(EyeReprojection, IdenticalEyesExchangeTheirLightExactly) {
  const FrameData a = planeFrame(0.0f, 3.0f), b = planeFrame(0.0f, 3.0f);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 5.0f);
  Plane3 la, lb;
  for (int c = 0; c < 3; ++c) {
    la[c].resize(W, H);
    lb[c].resize(W, H);
    for (auto& v : la[c].data) v = u(rng);
    for (auto& v : lb[c].data) v = u(rng);
  }
  Plane3 out = constant(0.0f);
  const ReprojectionSettings s;
  const size_t n = eyeReproject(EyeGuide::of(a), EyeGuide::of(b), s, 1.0f, la, lb, out);
  EXPECT_EQ(n, size_t(W * H));
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < out[c].data.size(); ++i)
      // Up to the float projection's error: the landing point is the pixel centre to ~1e-5 px.
      ASSERT_NEAR(out[c].data[i], lb[c].data[i], 5e-4f) << i;
}

TEST(EyeReprojection, SharingHalvesTheVarianceOfIndependentNoise) {
  const FrameData a = planeFrame(0.0f, 3.0f), b = planeFrame(0.0f, 3.0f);
  std::mt19937 rng(11);
  std::normal_distribution<float> noise(1.0f, 0.3f);
  Plane3 la, lb, out = constant(0.0f);
  for (int c = 0; c < 3; ++c) {
    la[c].resize(W, H);
    lb[c].resize(W, H);
    for (auto& v : la[c].data) v = noise(rng);
    for (auto& v : lb[c].data) v = noise(rng);
  }
  eyeReproject(EyeGuide::of(a), EyeGuide::of(b), ReprojectionSettings{}, 0.5f, la, lb, out);
  auto variance = [](const Plane& p) {
    double s = 0, s2 = 0;
    for (float v : p.data) s += v, s2 += double(v) * v;
    const double m = s / p.data.size();
    return s2 / p.data.size() - m * m;
  };
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(variance(out[c]) / variance(la[c]), 0.5, 0.05);
}

TEST(EyeReprojection, PointsBehindTheOtherCameraOrWithoutSurfaceStay) {
  FrameData a = planeFrame(0.0f, 3.0f);
  const FrameData b = planeFrame(0.0f, 3.0f);
  for (int c = 0; c < 3; ++c) a.plane(Buffer::Normal, c)(5, 5) = 0.0f;  // background pixel
  a.plane(Buffer::Position, 2)(6, 5) = 4.0f;                            // behind the camera
  Plane3 out = constant(0.0f);
  Plane moved(W, H);
  eyeReproject(EyeGuide::of(a), EyeGuide::of(b), ReprojectionSettings{}, 1.0f, constant(2.0f), constant(9.0f), out, &moved);
  EXPECT_EQ(moved(5, 5), 0.0f);
  EXPECT_EQ(out[0](5, 5), 2.0f);
  EXPECT_EQ(moved(6, 5), 0.0f);
  EXPECT_EQ(moved(7, 5), 1.0f);
  EXPECT_EQ(out[0](7, 5), 9.0f);
}

}  // namespace
}  // namespace rtd
