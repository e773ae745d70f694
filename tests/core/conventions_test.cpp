// Engine input conventions (rtd::FrameConventions): the conversion's numbers against
// hand-computed values, and per convention the same scene given natively and in that
// convention denoised to the same output, while ignoring the convention changes the output.
#include <gtest/gtest.h>

#include <cmath>

#include "core/conventions.h"
#include "support/convention_frames.h"

namespace rtd {
namespace {

using C = FrameConventions;

TEST(Conventions, DefaultsAreNativeAndConvertNothing) {
  C c;
  EXPECT_TRUE(c.native());
  const ConventionTransform t = conventionTransform(c, Camera{}, 64, 32, true);
  EXPECT_FALSE(t.convertsPlanes());
  EXPECT_FALSE(t.jitter);
  c.depthRange = C::DepthRange::MinusOneToOne;  // meaningless without hardware depth
  EXPECT_TRUE(c.native());
  c.jitterX = 0.25f;
  EXPECT_FALSE(c.native());
}

TEST(Conventions, MotionScaleAndOffset) {
  C c;
  c.motionUnits = C::MotionUnits::Uv;
  auto t = conventionTransform(c, Camera{}, 160, 90, false);
  EXPECT_EQ(t.motionScale[0], 160);
  EXPECT_EQ(t.motionScale[1], 90);
  c.motionUnits = C::MotionUnits::Ndc;
  c.motionYUp = true;
  t = conventionTransform(c, Camera{}, 160, 90, false);
  EXPECT_EQ(t.motionScale[0], 80);
  EXPECT_EQ(t.motionScale[1], -45);
  c.motionToCurrent = true;
  c.motionIncludesJitter = true;
  c.jitterX = 0.25f, c.jitterY = -0.125f, c.previousJitterX = -0.5f, c.previousJitterY = 0.375f;
  t = conventionTransform(c, Camera{}, 160, 90, false);
  EXPECT_EQ(t.motionScale[0], -80);
  EXPECT_EQ(t.motionScale[1], 45);
  // true motion = jittered motion + previous jitter - jitter
  EXPECT_EQ(t.motionOffset[0], -0.75f);
  EXPECT_EQ(t.motionOffset[1], 0.5f);
}

TEST(Conventions, HardwareDepthToLinear) {
  C c;
  c.depth = C::DepthKind::Hardware;
  const auto set = [&](const std::array<double, 16>& p) {
    for (int k = 0; k < 16; ++k) c.depthProjection[k] = float(p[k]);
    return conventionTransform(c, Camera{}, 8, 8, false);
  };
  // Vulkan/D3D [0, 1], near 0.5, far 20: d = 0 at the near plane, 1 at the far one, and at
  // depth z in between d = f (z - n) / (z (f - n)): (20/19.5)(1 - 0.5/2) = 0.76923 at z = 2.
  auto t = set(test::zeroToOneProjection(0.5, 20));
  EXPECT_NEAR(t.linearDepth(0.0f), 0.5f, 1e-6f);
  EXPECT_NEAR(t.linearDepth(1.0f), 20.0f, 1e-4f);  // the matrix in float: 2e-6 relative
  EXPECT_NEAR(t.linearDepth(float(20.0 / 19.5 * 0.75)), 2.0f, 1e-5f);
  // Reversed-Z, infinite far plane: d = n / depth; the cleared depth 0 is the far plane.
  t = set(test::reversedInfiniteProjection(0.1));
  EXPECT_NEAR(t.linearDepth(1.0f), 0.1f, 1e-7f);
  EXPECT_NEAR(t.linearDepth(0.025f), 4.0f, 1e-5f);
  EXPECT_EQ(t.linearDepth(0.0f), kFarDepth);
  // OpenGL: ndc in [-1, 1], the depth buffer (ndc + 1) / 2.
  c.depthRange = C::DepthRange::MinusOneToOne;
  t = set(test::openGlProjection(1, 9));
  EXPECT_NEAR(t.linearDepth(0.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(t.linearDepth(1.0f), 9.0f, 1e-5f);
  // depth 3: ndc = (-(10/8)(-3) - 18/8) / 3 = 0.5, d = 0.75
  EXPECT_NEAR(t.linearDepth(0.75f), 3.0f, 1e-5f);
}

TEST(Conventions, ViewSpaceNormalsAreRotatedByTheCamera) {
  // A camera turned 90 degrees to the left (yaw +90 about y): its view direction -z is world -x,
  // so a normal facing the camera (view +z) faces world +x; view +x (right) is world -z.
  Camera cam;
  cam.worldToCamera = {0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1};  // R^T, R = yaw(+90)
  cam.valid = true;
  C c;
  c.normalSpace = C::NormalSpace::View;
  const auto t = conventionTransform(c, cam, 2, 1, true);
  ASSERT_TRUE(t.normals);
  FrameData f;
  f.width = 2, f.height = 1;
  f.buffers[int(Buffer::Normal)].resize(3);
  for (auto& p : f.buffers[int(Buffer::Normal)]) p.resize(2, 1);
  const float view[2][3] = {{0, 0, 1}, {2, 0, 0}}, world[2][3] = {{1, 0, 0}, {0, 0, -1}};  // renormalized
  for (int x = 0; x < 2; ++x)
    for (int k = 0; k < 3; ++k) f.plane(Buffer::Normal, k)(x, 0) = view[x][k];
  applyConventions(t, f);
  for (int x = 0; x < 2; ++x)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(f.plane(Buffer::Normal, k)(x, 0), world[x][k], 1e-6f);
  // Without a camera, view-space normals are an error (and only when the frame has normals).
  EXPECT_THROW(conventionTransform(c, Camera{}, 2, 1, true), Error);
  EXPECT_NO_THROW(conventionTransform(c, Camera{}, 2, 1, false));
}

TEST(Conventions, JitterShiftsTheCameraDerivedHistoryPosition) {
  // A point that projects to pixel position (u, v) with the previous camera lands at
  // (u - jitterX, v - jitterY) with the compensated one.
  Camera prev;
  prev.projection = {1.2f, 0, 0.1f, 0, 0, 1.7f, -0.05f, 0, 0, 0, -1.01f, -0.2f, 0, 0, -1, 0};
  prev.valid = true;
  C c;
  c.jitterX = 0.3f, c.jitterY = -0.45f;
  const int w = 64, h = 40;
  const auto t = conventionTransform(c, prev, w, h, false);
  const Camera comp = jitterCompensated(prev, t, w, h);
  auto toPixels = [&](const Camera& cam, float x, float y, float z) {
    float clip[4];
    for (int r = 0; r < 4; ++r)
      clip[r] = cam.projection[r * 4] * x + cam.projection[r * 4 + 1] * y + cam.projection[r * 4 + 2] * z + cam.projection[r * 4 + 3];
    return std::array<float, 2>{(clip[0] / clip[3] * 0.5f + 0.5f) * w, (0.5f - clip[1] / clip[3] * 0.5f) * h};
  };
  for (auto p : {std::array<float, 3>{0.3f, -0.2f, -3.0f}, std::array<float, 3>{-1.0f, 0.5f, -7.5f}}) {
    const auto a = toPixels(prev, p[0], p[1], p[2]), b = toPixels(comp, p[0], p[1], p[2]);
    EXPECT_NEAR(b[0], a[0] - 0.3f, 1e-4f);
    EXPECT_NEAR(b[1], a[1] + 0.45f, 1e-4f);
  }
}

TEST(Conventions, ByName) {
  C c;
  setConvention(c, "motionUnits", "ndc");
  setConvention(c, "motionYUp", "true");
  setConvention(c, "jitterX", "0.25");
  setConvention(c, "depth", "hardware");
  EXPECT_EQ(c.motionUnits, C::MotionUnits::Ndc);
  EXPECT_TRUE(c.motionYUp);
  EXPECT_EQ(c.jitterX, 0.25f);
  EXPECT_EQ(c.depth, C::DepthKind::Hardware);
  const C before = c;
  EXPECT_THROW(setConvention(c, "motionUnit", "uv"), Error);
  EXPECT_THROW(setConvention(c, "motionUnits", "meters"), Error);
  EXPECT_THROW(setConvention(c, "jitterX", "2"), Error);  // outside [-1, 1]
  EXPECT_EQ(c.motionUnits, before.motionUnits);
  EXPECT_EQ(c.jitterX, before.jitterX);
  bool listed = false;
  for (const auto& s : conventionSettings(c))
    if (s.name == "depth") listed = s.value == "hardware" && s.choices.size() == 2;
  EXPECT_TRUE(listed);
}

TEST(Conventions, TypedConventionsAreCheckedLikeNamedOnes) {
  auto device = Device::create();
  auto den = device->createDenoiser("accumulate");
  Image color(8, 4, 3, 0.5f), out(8, 4, 3);
  FrameInputs in;
  in[Buffer::Color] = color.view();
  in.conventions.jitterX = 5;  // outside [-1, 1]
  EXPECT_THROW(den->denoise(in, out.view()), Error);
  in.conventions = {};
  in.conventions.motionUnits = C::MotionUnits(7);
  EXPECT_THROW(den->denoise(in, out.view()), Error);
  in.conventions = {};
  in.conventions.depthProjection[10] = NAN;
  EXPECT_THROW(den->denoise(in, out.view()), Error);
  in.conventions = {};
  EXPECT_NO_THROW(den->denoise(in, out.view()));
}

// ---- The same scene in each convention gives the same output (SVGF: motion, normals, depth).
// Measured on this scene: motion conversions exact; positions and cameras, view-space normals
// and reversed-Z depth about 1e-6 of the peak; standard-Z depth 1e-5 (float depth buffers lose
// precision away from the near plane); ignoring the convention 5-30%.

synthetic::Scene conventionsScene() {
  synthetic::Scene s;
  s.gradientSamples = false;  // A-SVGF's; they do not follow the camera's yaw and jitter
  s.width = 64;
  s.height = 40;
  return s;
}

void expectSameOutput(const synthetic::Scene& s, const test::ToEngine& engine, double tolerance) {
  auto device = Device::create();
  test::expectSameOutput(*device, s, engine, tolerance);
}

TEST(Conventions, MotionInUv) { expectSameOutput(conventionsScene(), test::motionAs(C::MotionUnits::Uv, false, false), 1e-5); }
TEST(Conventions, MotionInNdcYUpPointingToCurrent) {
  expectSameOutput(conventionsScene(), test::motionAs(C::MotionUnits::Ndc, true, true), 1e-5);
}
TEST(Conventions, MotionIncludingJitter) {
  auto s = conventionsScene();
  s.jitter = true;
  expectSameOutput(s, test::jitteredMotion(s), 1e-5);
}
TEST(Conventions, JitteredCameraWithoutMotionVectors) {
  auto s = conventionsScene();
  s.jitter = true;
  expectSameOutput(s, test::jitteredCameraOnly(s), 1e-5);
}
TEST(Conventions, ViewSpaceNormals) {
  auto s = conventionsScene();
  s.cameraYawSpeed = 0.03f;
  expectSameOutput(s, test::viewSpaceNormals(), 1e-5);
}
TEST(Conventions, HardwareDepthZeroToOne) {
  expectSameOutput(conventionsScene(), test::hardwareDepth(test::zeroToOneProjection(0.1, 100), C::DepthRange::ZeroToOne), 1e-4);
}
TEST(Conventions, HardwareDepthOpenGl) {
  expectSameOutput(conventionsScene(), test::hardwareDepth(test::openGlProjection(0.1, 100), C::DepthRange::MinusOneToOne), 1e-4);
}
TEST(Conventions, HardwareDepthReversedInfinite) {
  expectSameOutput(conventionsScene(), test::hardwareDepth(test::reversedInfiniteProjection(0.1), C::DepthRange::ZeroToOne), 1e-5);
}

// A frame whose conventions cannot be applied is rejected before history changes.
TEST(Conventions, ViewSpaceNormalsWithoutCameraAreRejectedAndLoseNothing) {
  auto device = Device::create();
  auto a = device->createDenoiser("svgf"), b = device->createDenoiser("svgf");
  const auto s = conventionsScene();
  Image outA(s.width, s.height, 3), outB(s.width, s.height, 3);
  for (int i = 0; i < 3; ++i) {
    const Frame f = synthetic::makeFrame(s, i);
    FrameInputs bad = f.inputs();
    bad.camera.valid = false;
    bad.conventions.normalSpace = C::NormalSpace::View;
    EXPECT_THROW(b->denoise(bad, outB.view()), Error);
    a->denoise(f.inputs(), outA.view());
    b->denoise(f.inputs(), outB.view());
    ASSERT_EQ(outA.pixels, outB.pixels) << "frame " << i;
  }
}

}  // namespace
}  // namespace rtd
