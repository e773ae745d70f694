// Feature buffers against closed-form values: depth and its gradient on planes, sphere normals,
// mirror features of a flat mirror reflecting a known quad, motion vectors for camera and object
// motion (checked through the stored camera matrices), and stereo eye placement.
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <array>

#include "render/render_test_util.h"

namespace rtd::render::test {
namespace {

/// Camera basis and eye recovered from the stored matrices (independent of the renderer's code).
struct CameraGeom {
  Vec eye, right, up, forward;
  double tanHalf, aspect;
  explicit CameraGeom(const Camera& c) {
    const auto& m = c.worldToCamera;
    right = {m[0], m[1], m[2]};
    up = {m[4], m[5], m[6]};
    forward = {-m[8], -m[9], -m[10]};
    const Vec t = {m[3], m[7], m[11]};
    // eye = -R^T t
    eye = {-(m[0] * t[0] + m[4] * t[1] + m[8] * t[2]), -(m[1] * t[0] + m[5] * t[1] + m[9] * t[2]),
           -(m[2] * t[0] + m[6] * t[1] + m[10] * t[2])};
    tanHalf = 1.0 / c.projection[5];
    aspect = c.projection[5] / c.projection[0];
  }
  Vec ray(double px, double py, int w, int h) const {
    const double sx = (2 * px / w - 1) * tanHalf * aspect, sy = (1 - 2 * py / h) * tanHalf;
    return norm(add(forward, add(scale(right, sx), scale(up, sy))));
  }
};

TEST(RenderFeatures, DepthNormalPositionOfAFacingPlane) {
  auto scene = sceneFromJson(R"({
    "objects": [{"shape": "quad", "translation": [0, 0, -5], "rotation": [90, 0, 0], "scale": 100}],
    "sky": {"color": 1}, "camera": {"position": [0, 0, 0], "target": [0, 0, -1], "fov": 50}
  })");
  Renderer r(scene, tiny(16, 10));
  const Frame f = r.render(0);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 16; ++x) {
      EXPECT_NEAR(f[Buffer::Depth].at(x, y), 5.0, 1e-4);
      EXPECT_NEAR(f[Buffer::DepthGradient].at(x, y, 0), 0.0, 1e-4);
      EXPECT_NEAR(f[Buffer::DepthGradient].at(x, y, 1), 0.0, 1e-4);
      EXPECT_NEAR(f[Buffer::Position].at(x, y, 2), -5.0, 1e-4);
      EXPECT_NEAR(f[Buffer::Normal].at(x, y, 2), 1.0, 1e-6);
      EXPECT_EQ(f[Buffer::ObjectId].at(x, y), 1.0f);
    }
}

TEST(RenderFeatures, DepthAndDepthGradientOfATiltedFloor) {
  auto scene = sceneFromJson(R"({
    "objects": [{"shape": "quad", "scale": 400}],
    "sky": {"color": 1}, "camera": {"position": [0.3, 2, 0], "target": [0, 0, -4], "fov": 40}
  })");
  const int w = 20, h = 12;
  Renderer r(scene, tiny(w, h));
  const Frame f = r.render(0);
  const CameraGeom cam(f.camera);
  auto depthAt = [&](double px, double py) {
    const Vec d = cam.ray(px, py, w, h);
    const double t = -cam.eye[1] / d[1];
    return t * dot(d, cam.forward);
  };
  for (int y = h / 2; y < h; ++y)  // the floor fills the lower half
    for (int x = 0; x < w; ++x) {
      const Vec d = cam.ray(x + 0.5, y + 0.5, w, h);
      ASSERT_LT(d[1], 0);
      const double t = -cam.eye[1] / d[1];
      const Vec p = add(cam.eye, scale(d, t));
      const double depth = depthAt(x + 0.5, y + 0.5);
      EXPECT_NEAR(f[Buffer::Depth].at(x, y), depth, 1e-4 * depth);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[Buffer::Position].at(x, y, c), p[c], 1e-4 * (1 + std::fabs(p[c])));
      EXPECT_NEAR(f[Buffer::DepthGradient].at(x, y, 0), depthAt(x + 1.5, y + 0.5) - depth, 1e-3 * depth);
      EXPECT_NEAR(f[Buffer::DepthGradient].at(x, y, 1), depthAt(x + 0.5, y + 1.5) - depth, 1e-3 * depth);
      EXPECT_NEAR(f[Buffer::Normal].at(x, y, 1), 1.0, 1e-6);
    }
}

TEST(RenderFeatures, SphereNormalsAreRadial) {
  auto scene = sceneFromJson(R"({
    "objects": [{"shape": "sphere", "translation": [0.2, -0.1, 0], "scale": 2}],
    "sky": {"color": 1}, "camera": {"position": [0, 0, 4], "target": [0, 0, 0], "fov": 40}
  })");
  Renderer r(scene, tiny(24, 24));
  const Frame f = r.render(0);
  int hits = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      if (f[Buffer::ObjectId].at(x, y) != 1.0f) continue;
      ++hits;
      const Vec p = sub(px3(f[Buffer::Position], x, y), Vec{0.2, -0.1, 0});
      EXPECT_NEAR(std::sqrt(dot(p, p)), 1.0, 0.01);  // tessellated surface within 1%
      const Vec n = px3(f[Buffer::Normal], x, y), expected = norm(p);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(n[c], expected[c], 1e-4);
    }
  EXPECT_GT(hits, 150);
}

// A mirror floor reflects a vertical quad of known albedo at z = -3: for mirror pixels whose
// mirrored ray hits the quad, the reflection features equal the analytic intersection.
TEST(RenderFeatures, FlatMirrorReflectsKnownQuad) {
  auto scene = sceneFromJson(R"({
    "objects": [
      {"shape": "quad", "scale": 40, "material": {"mirror": true}},
      {"shape": "quad", "translation": [0, 1, -3], "rotation": [90, 0, 0], "scale": [4, 1, 2],
       "material": {"baseColor": [0.2, 0.5, 0.7], "roughness": 1, "specular": 0}}
    ],
    "sky": {"color": 1}, "camera": {"position": [0, 1, 3], "target": [0, 0.2, -1], "fov": 60}
  })");
  const int w = 32, h = 24;
  Renderer r(scene, tiny(w, h));
  const Frame f = r.render(0);
  const CameraGeom cam(f.camera);
  int quadHits = 0, skyHits = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (f[Buffer::ObjectId].at(x, y) != 1.0f) {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(f[Buffer::ReflectedAlbedo].at(x, y, c), 0.0f);  // not a mirror pixel
        continue;
      }
      EXPECT_EQ(f[Buffer::Metalness].at(x, y), 1.0f);
      EXPECT_EQ(f[Buffer::Roughness].at(x, y), 0.0f);
      const Vec p = px3(f[Buffer::Position], x, y);
      const Vec d = norm(sub(p, cam.eye));
      const Vec refl = {d[0], -d[1], d[2]};
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[Buffer::MirrorDirection].at(x, y, c), refl[c], 1e-4);
      const double t = refl[2] < 0 ? (-3 - p[2]) / refl[2] : -1;
      const Vec q = add(p, scale(refl, t));
      if (t > 0 && std::fabs(q[0]) < 1.9 && q[1] > 0.05 && q[1] < 1.95) {
        ++quadHits;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[Buffer::ReflectedPosition].at(x, y, c), q[c], 2e-3);
        EXPECT_NEAR(f[Buffer::ReflectedNormal].at(x, y, 2), 1.0, 1e-5);  // faces the mirrored ray
        EXPECT_NEAR(f[Buffer::ReflectedAlbedo].at(x, y, 0), 0.2, 1e-6);
        EXPECT_NEAR(f[Buffer::ReflectedAlbedo].at(x, y, 1), 0.5, 1e-6);
        EXPECT_NEAR(f[Buffer::ReflectedAlbedo].at(x, y, 2), 0.7, 1e-6);
        EXPECT_NEAR(f[Buffer::SecondaryDistance].at(x, y), t, 2e-3);
      } else if (t < 0 || q[1] > 2.1 || std::fabs(q[0]) > 2.1) {
        ++skyHits;  // the mirrored ray escapes: albedo 1 (nothing to demodulate), distance 0
        EXPECT_EQ(f[Buffer::ReflectedAlbedo].at(x, y, 0), 1.0f);
        EXPECT_EQ(f[Buffer::SecondaryDistance].at(x, y), 0.0f);
      }
    }
  EXPECT_GT(quadHits, 60);
  EXPECT_GT(skyHits, 10);
}

// Motion vectors: reprojecting each pixel's world position with the previous frame's camera
// (matrices as stored in the frame) and, for moving objects, the previous object transform
// known from the scene's keyframes, lands where the motion vector says.
TEST(RenderFeatures, MotionVectorsMatchReprojectionForCameraAndObjectMotion) {
  auto scene = Scene::load("dynamic");  // camera moves; ball translates, box spins (docs/renderer.md)
  const int w = 64, h = 36, frame = 10;
  Renderer r(scene, tiny(w, h));
  const Frame prev = r.render(frame - 1), cur = r.render(frame);
  int checked[3] = {0, 0, 0}, skyChecked = 0;
  const double spin = 120.0 / 47.0 * 3.14159265358979 / 180.0;  // box: 0 -> 120 degrees over frames 0..47
  const Vec boxCentre = {-0.5, 0.35, -0.9};
  const Vec ballStep = {2.0 / 24.0, 0.0, 0.6 / 24.0};  // ball: (-1.8,.4,.2) at 0 -> (0.2,.4,.8) at 24
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float id = cur[Buffer::ObjectId].at(x, y);
      if (id == 0) {
        // Background: a direction at infinity moves with the camera's rotation only.
        const Vec d = CameraGeom(cur.camera).ray(x + 0.5, y + 0.5, w, h);
        const auto pp = projectWithMatrices(prev.camera, add(CameraGeom(prev.camera).eye, scale(d, 1e3)), w, h);
        EXPECT_NEAR(x + 0.5 + cur[Buffer::Motion].at(x, y, 0), pp[0], 2e-2);
        EXPECT_NEAR(y + 0.5 + cur[Buffer::Motion].at(x, y, 1), pp[1], 2e-2);
        ++skyChecked;
        continue;
      }
      Vec p = px3(cur[Buffer::Position], x, y);
      int kind = 0;
      if (id == 5) {  // ball
        p = sub(p, ballStep);
        kind = 1;
      } else if (id == 6) {  // box: rotate back about its centre by one frame's spin (about +Y)
        const Vec q = sub(p, boxCentre);
        const double c = std::cos(-spin), s = std::sin(-spin);
        p = add(boxCentre, Vec{c * q[0] + s * q[2], q[1], -s * q[0] + c * q[2]});
        kind = 2;
      } else if (id == 7) {
        continue;  // the lamp moves too, covered by the same code path as the ball
      }
      const auto pp = projectWithMatrices(prev.camera, p, w, h);
      EXPECT_NEAR(x + 0.5 + cur[Buffer::Motion].at(x, y, 0), pp[0], 2e-2) << "pixel " << x << "," << y << " kind " << kind;
      EXPECT_NEAR(y + 0.5 + cur[Buffer::Motion].at(x, y, 1), pp[1], 2e-2) << "pixel " << x << "," << y << " kind " << kind;
      ++checked[kind];
    }
  EXPECT_GT(checked[0], 500);
  EXPECT_GT(checked[1], 15);
  EXPECT_GT(checked[2], 15);
  EXPECT_GT(skyChecked, 20);
}

TEST(RenderFeatures, StereoEyesAreSeparatedAlongTheRightAxis) {
  auto scene = sceneFromJson(R"({
    "objects": [{"shape": "quad", "translation": [0, 0, -5], "rotation": [90, 0, 0], "scale": 100}],
    "sky": {"color": 1}, "camera": {"position": [1, 2, 3], "target": [1, 2, -1], "fov": 50}
  })");
  RenderSettings s = tiny(16, 8);
  s.eyeDistance = 0.1f;
  Renderer r(scene, s);
  const Frame left = r.render(0, Eye::Left), right = r.render(0, Eye::Right), centre = r.render(0);
  const CameraGeom l(left.camera), rr(right.camera), c(centre.camera);
  const Vec sep = sub(rr.eye, l.eye);
  EXPECT_NEAR(sep[0], 0.1, 1e-5);
  EXPECT_NEAR(sep[1], 0.0, 1e-5);
  EXPECT_NEAR(sep[2], 0.0, 1e-5);
  const Vec mid = scale(add(l.eye, rr.eye), 0.5);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mid[k], c.eye[k], 1e-5);
  // Parallel cameras: the same pixel sees points 0.1 apart on a plane parallel to the image.
  for (int x = 0; x < 16; ++x)
    EXPECT_NEAR(right[Buffer::Position].at(x, 4, 0) - left[Buffer::Position].at(x, 4, 0), 0.1, 1e-4);
}

}  // namespace
}  // namespace rtd::render::test
#endif
