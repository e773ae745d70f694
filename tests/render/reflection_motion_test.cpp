// Reflection motion vectors end to end (Voorhuis Sec. 4.1, checklist item 10): a flat mirror
// floor under a camera translating sideways. The reflected geometry's screen motion is known
// analytically: the point X seen in the mirror is the virtual point X' (X mirrored in the floor
// plane) seen directly, so its previous position is the previous camera's projection of X'.
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/frame_data.h"
#include "passes/reflection_reprojection.h"
#include "render/render_test_util.h"

namespace rtd::render::test {
namespace {

// A mirror floor (y = 0) with a textured wall and two boxes standing on it; the camera slides
// along x at constant height and direction (a pure translation).
constexpr const char* kMirrorFloor = R"({
  "materials": {
    "mirror": {"baseColor": [0.9, 0.9, 0.9], "mirror": true},
    "wall": {"baseColor": [0.7, 0.6, 0.5], "roughness": 1, "specular": 0, "checker": {"color": [0.2, 0.3, 0.6], "cells": 12}},
    "box": {"baseColor": [0.8, 0.3, 0.2], "roughness": 1, "specular": 0}
  },
  "objects": [
    {"shape": "quad", "scale": 40, "material": "mirror"},
    {"shape": "quad", "translation": [0, 2, -4], "rotation": [90, 0, 0], "scale": [12, 1, 4], "material": "wall"},
    {"shape": "box", "translation": [-1, 0.5, -1.5], "scale": 1, "material": "box"},
    {"shape": "box", "translation": [1.4, 0.35, -2.2], "scale": 0.7, "material": "wall"}
  ],
  "sky": {"color": 0.5},
  "frames": 8,
  "camera": {"fov": 55, "keyframes": [
    {"frame": 0, "position": [-0.8, 1.2, 3], "target": [-0.8, 0.4, -1]},
    {"frame": 7, "position": [0.8, 1.2, 3], "target": [0.8, 0.4, -1]}
  ]}
})";

TEST(ReflectionMotion, MirrorFloorMatchesAnalyticVirtualImageMotion) {
  const int w = 80, h = 56;
  Renderer r(sceneFromJson(kMirrorFloor), tiny(w, h));
  const Frame f0 = r.render(3), f1 = r.render(4);
  FrameData prev, cur;
  importFrame(f0.inputs(), {Buffer::Color}, prev);
  importFrame(f1.inputs(), {Buffer::Color}, cur);
  PixelVector<uint8_t> cls, prevCls;
  classifySurfaces(cur, {}, false, cls);
  classifySurfaces(prev, {}, false, prevCls);
  Reprojection primary;
  reproject(cur, &prev, ReprojectionSettings{}, primary);
  ReflectionSearchFeatures prevFeatures;
  prevFeatures.build(prev, prevCls);

  int compared = 0, within = 0, primaryWithin = 0, quadraticWithin = 0;
  double sumError = 0, sumQuadratic = 0, sumInteger = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (SurfaceClass(cls[i]) != SurfaceClass::Mirror) continue;
      const float X[3] = {cur.plane(Buffer::ReflectedPosition, 0).data[i], cur.plane(Buffer::ReflectedPosition, 1).data[i],
                          cur.plane(Buffer::ReflectedPosition, 2).data[i]};
      if (cur.plane(Buffer::ReflectedNormal, 1).data[i] == 0 && cur.plane(Buffer::ReflectedNormal, 2).data[i] == 0 &&
          cur.plane(Buffer::ReflectedNormal, 0).data[i] == 0)
        continue;  // the mirror shows the sky
      const auto [ax, ay] = projectWithMatrices(prev.camera, {X[0], -X[1], X[2]}, w, h);  // in front: the camera looks down
      if (ax < 1 || ay < 1 || ax > w - 1 || ay > h - 1) continue;
      // The analytic position must show the same point in the previous frame (not occluded,
      // not at a depth edge of the reflection): checked on its pixel.
      const size_t j = size_t(ay) * w + size_t(ax);
      if (SurfaceClass(prevCls[j]) != SurfaceClass::Mirror) continue;
      float d2 = 0;
      for (int k = 0; k < 3; ++k) {
        const float d = prev.plane(Buffer::ReflectedPosition, k).data[j] - X[k];
        d2 += d * d;
      }
      if (d2 > 0.05f * 0.05f) continue;
      DiamondSearchOptions eq23;  // the paper's Eqs. 2-3
      eq23.fit = SubpixelFit::inverseDistance;
      const SearchResult s = searchReflection(cur, prevFeatures, cls, prevCls, primary, x, y, eq23);
      ASSERT_TRUE(s.found());
      const double e = std::hypot(s.matchX - ax, s.matchY - ay);
      sumError += e;
      ++compared;
      within += e <= 1.0;
      // The quadratic fit (SubpixelFit::quadratic, the default) from the same search, and no refinement.
      const SearchResult q = searchReflection(cur, prevFeatures, cls, prevCls, primary, x, y, DiamondSearchOptions{});
      const double eq = std::hypot(q.matchX - ax, q.matchY - ay);
      sumQuadratic += eq;
      quadraticWithin += eq <= 1.0;
      sumInteger += std::hypot(s.bestX + 0.5 - ax, s.bestY + 0.5 - ay);
      primaryWithin += std::hypot(primary.prevX.data[i] - ax, primary.prevY.data[i] - ay) <= 1.0;
    }
  ASSERT_GT(compared, 400);
  EXPECT_GE(double(within) / compared, 0.97) << within << " of " << compared;
  EXPECT_LT(sumError / compared, 0.35);
  // The floor's reflected world positions are locally close to linear in the pixel: the
  // quadratic fit is far closer to the analytic motion than Eqs. 2-3 and than the best pixel.
  std::printf("mean error to the analytic motion: Eqs. 2-3 %.4f px, quadratic %.4f px, best pixel %.4f px\n",
              sumError / compared, sumQuadratic / compared, sumInteger / compared);
  EXPECT_GE(double(quadraticWithin) / compared, 0.97);
  EXPECT_LT(sumQuadratic / compared, 0.5 * sumError / compared);
  // The primary hit moves differently from its reflection: primary motion is wrong here.
  EXPECT_LT(double(primaryWithin) / compared, 0.5);
}


// A mirror floor and a glossy panel (roughness 0.2: GlossyReflection) under the sliding camera,
// with sky above the wall, so that some mirror pixels show the sky.
constexpr const char* kMirrorAndGlossy = R"({
  "materials": {
    "mirror": {"baseColor": [0.9, 0.9, 0.9], "mirror": true},
    "glossy": {"baseColor": [0.6, 0.6, 0.7], "roughness": 0.2, "metallic": 1},
    "wall": {"baseColor": [0.7, 0.6, 0.5], "roughness": 1, "specular": 0, "checker": {"color": [0.2, 0.3, 0.6], "cells": 12}}
  },
  "objects": [
    {"shape": "quad", "scale": 40, "material": "mirror"},
    {"shape": "quad", "translation": [0, 1, -4], "rotation": [90, 0, 0], "scale": [12, 1, 1], "material": "wall"},
    {"shape": "quad", "translation": [-1.5, 0.8, -2], "rotation": [80, 30, 0], "scale": [1.2, 1, 0.8], "material": "glossy"},
    {"shape": "box", "translation": [1.2, 0.4, -1.8], "scale": 0.8, "material": "wall"}
  ],
  "sky": {"color": 0.5},
  "frames": 8,
  "camera": {"fov": 60, "keyframes": [
    {"frame": 0, "position": [-0.8, 1.0, 3], "target": [-0.8, 0.6, -1]},
    {"frame": 7, "position": [0.8, 1.0, 3], "target": [0.8, 0.6, -1]}
  ]}
})";

// The search reads each previous pixel's feature from ReflectionSearchFeatures, built once per
// frame. Here every searched pixel's result is held against Algorithm 1 run with distance
// functions that compute the features from the previous frame's planes at each tap (as the
// search did before the records existed): Eq. 1 on the reflected position, a sky mirror's
// point kMissDepth along its mirror direction, Eq. 5 on the representative rays.
TEST(ReflectionMotion, SearchFeaturesGiveTheSearchOfThePlanesThemselves) {
  const int w = 96, h = 64;
  Renderer r(sceneFromJson(kMirrorAndGlossy), tiny(w, h));
  const Frame f0 = r.render(2), f1 = r.render(3);
  FrameData prev, cur;
  importFrame(f0.inputs(), {Buffer::Color}, prev);
  importFrame(f1.inputs(), {Buffer::Color}, cur);
  PixelVector<uint8_t> cls, prevCls;
  classifySurfaces(cur, {}, false, cls);
  classifySurfaces(prev, {}, false, prevCls);
  Reprojection primary;
  reproject(cur, &prev, ReprojectionSettings{}, primary);
  Reprojection out;
  ReflectionMotionStats stats;
  specularReprojection(cur, &prev, cls, prevCls, primary, SpecularMotion::Reflection, {}, out, &stats);

  auto plane = [](const FrameData& f, Buffer b, int k, size_t i) { return f.plane(b, k).data[i]; };
  auto mirrorPoint = [&](const FrameData& f, size_t i, float p[3]) {
    float n2 = 0, d2 = 0;
    for (int k = 0; k < 3; ++k) {
      n2 += plane(f, Buffer::ReflectedNormal, k, i) * plane(f, Buffer::ReflectedNormal, k, i);
      d2 += plane(f, Buffer::MirrorDirection, k, i) * plane(f, Buffer::MirrorDirection, k, i);
    }
    const bool sky = n2 < 0.25f;
    const float s = d2 > 0 ? kMissDepth / std::sqrt(d2) : 0.0f;
    for (int k = 0; k < 3; ++k)
      p[k] = sky ? plane(f, Buffer::Position, k, i) + plane(f, Buffer::MirrorDirection, k, i) * s
                 : plane(f, Buffer::ReflectedPosition, k, i);
    return sky;
  };
  auto ray = [&](const FrameData& f, size_t i) {
    RepresentativeRay q;
    float d2 = 0;
    for (int k = 0; k < 3; ++k) {
      q.o[k] = plane(f, Buffer::Position, k, i);
      q.d[k] = plane(f, Buffer::MirrorDirection, k, i);
      d2 += q.d[k] * q.d[k];
    }
    const float inv = d2 > 0 ? 1.0f / std::sqrt(d2) : 0.0f;
    for (float& v : q.d) v *= inv;
    const float depth = plane(f, Buffer::SecondaryDistance, 0, i);
    q.depth = depth > 0 ? depth : kMissDepth;
    return q;
  };
  int mirrors = 0, skies = 0, glossy = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const SurfaceClass c = SurfaceClass(cls[i]);
      if (c != SurfaceClass::Mirror && c != SurfaceClass::GlossyReflection) continue;
      SearchResult direct;
      if (c == SurfaceClass::Mirror) {
        float p[3];
        skies += mirrorPoint(cur, i, p);
        ++mirrors;
        direct = diamondSearch(x, y, primary.prevX.data[i], primary.prevY.data[i], w, h, [&](int qx, int qy) {
          const size_t j = size_t(qy) * w + qx;
          if (SurfaceClass(prevCls[j]) != SurfaceClass::Mirror) return kNoMatch;
          float q[3];
          mirrorPoint(prev, j, q);
          return worldDistance(p, q);
        });
      } else {
        const RepresentativeRay rp = ray(cur, i);
        ++glossy;
        direct = diamondSearch(x, y, primary.prevX.data[i], primary.prevY.data[i], w, h, [&](int qx, int qy) {
          const size_t j = size_t(qy) * w + qx;
          if (SurfaceClass(prevCls[j]) != SurfaceClass::GlossyReflection) return kNoMatch;
          return glossyDistance(rp, ray(prev, j));
        });
      }
      ASSERT_TRUE(direct.found()) << x << ", " << y;
      EXPECT_EQ(out.prevX.data[i], direct.matchX) << x << ", " << y;
      EXPECT_EQ(out.prevY.data[i], direct.matchY) << x << ", " << y;
    }
  // Both classes and sky mirrors are there to be compared.
  EXPECT_GT(mirrors, 300);
  EXPECT_GT(skies, 20);
  EXPECT_GT(glossy, 100);
  EXPECT_EQ(stats.mirrorPixels, uint64_t(mirrors));
  EXPECT_EQ(stats.glossyPixels, uint64_t(glossy));
}

}  // namespace
}  // namespace rtd::render::test
#endif
