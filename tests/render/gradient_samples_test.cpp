// The renderer's A-SVGF gradient samples (docs/renderer.md "Gradient samples"; checklist items
// 19 and 20 of shared/notes/denoiser-comparison-higginson.md): one sample per 3x3 stratum, the
// previous frame's brightest, forward-projected (camera and object motion) and re-shaded with
// its old seed; and the gradient asvgf computes from them.
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <cstring>

#include "core/frame_data.h"
#include "methods/asvgf/asvgf_passes.h"
#include "support/strata_gradient.h"
#include "render/render_test_util.h"

namespace rtd::render::test {
namespace {

constexpr int kW = 96, kH = 54;

// Pixels holding a gradient sample; at most one per stratum is checked on the way.
std::vector<std::pair<int, int>> samplePixels(const Frame& f) {
  std::vector<std::pair<int, int>> out;
  std::vector<int> perStratum(size_t(asvgf::strata(f.width)) * asvgf::strata(f.height), 0);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      if (f[Buffer::GradientSample].at(x, y) != 0.0f) {
        EXPECT_EQ(f[Buffer::GradientSample].at(x, y), 1.0f);
        ++perStratum[size_t(y / 3) * asvgf::strata(f.width) + x / 3];
        out.push_back({x, y});
      }
  for (int n : perStratum) EXPECT_LE(n, 1);
  return out;
}

float lum(const Frame& f, int x, int y) {
  const float* p = f[Buffer::Color].pixel(x, y);
  return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
}

using rtd::test::strataGradient;

TEST(GradientSamples, StaticSceneAndCameraReproduceEverySampleExactly) {
  // Checklist 19: area light, glossy and diffuse surfaces, nothing moves.
  auto scene = sceneFromJson(R"({
    "frames": 3,
    "objects": [
      {"shape": "quad", "scale": 6, "material": {"baseColor": 0.7, "roughness": 0.4}},
      {"shape": "box", "translation": [-0.6, 0.4, 0], "scale": 0.8, "material": {"baseColor": [0.2, 0.4, 0.8], "roughness": 0.2}},
      {"shape": "sphere", "translation": [0.7, 0.5, 0.3], "material": {"baseColor": [0.9, 0.8, 0.4], "metallic": 1, "roughness": 0.3}},
      {"shape": "quad", "translation": [0, 2.5, 0], "rotation": [180, 0, 0], "scale": [1.5, 1, 1.5], "material": {"emissive": 8}}
    ],
    "sky": {"color": 0.1},
    "camera": {"position": [0, 2, 4], "target": [0, 0.4, 0], "fov": 55}
  })");
  Renderer r(scene, tiny(kW, kH));
  const Frame f0 = r.render(0), f1 = r.render(1), f2 = r.render(2);
  EXPECT_TRUE(samplePixels(f0).empty());  // no previous frame, no samples (the buffers exist)
  auto check = [&](const Frame& prev, const Frame& cur) {
    const auto samples = samplePixels(cur);
    // Every stratum that sees geometry (not only the sky) gets its sample.
    int withGeometry = 0;
    for (int sy = 0; sy < asvgf::strata(kH); ++sy)
      for (int sx = 0; sx < asvgf::strata(kW); ++sx) {
        bool any = false;
        for (int y = 3 * sy; y < std::min(kH, 3 * sy + 3); ++y)
          for (int x = 3 * sx; x < std::min(kW, 3 * sx + 3); ++x) any = any || prev[Buffer::ObjectId].at(x, y) > 0;
        withGeometry += any;
      }
    EXPECT_GT(withGeometry, asvgf::strata(kW) * asvgf::strata(kH) / 2);
    EXPECT_EQ(int(samples.size()), withGeometry);
    for (auto [x, y] : samples) {
      // The identity projection: the sample is the previous frame's brightest of its stratum,
      // re-shaded at the same point with the same seed: exactly its previous value.
      EXPECT_EQ(cur[Buffer::GradientCurrent].at(x, y), cur[Buffer::GradientPrevious].at(x, y)) << x << "," << y;
      EXPECT_EQ(cur[Buffer::GradientPrevious].at(x, y), lum(prev, x, y));
      for (int v = y / 3 * 3; v < std::min(kH, y / 3 * 3 + 3); ++v)
        for (int u = x / 3 * 3; u < std::min(kW, x / 3 * 3 + 3); ++u)
          if (prev[Buffer::ObjectId].at(u, v) > 0) { EXPECT_GE(lum(prev, x, y), lum(prev, u, v)); }  // the sky is no candidate
    }
    // So G = 0 in every stratum.
    const asvgf::GradientImage g = strataGradient(cur);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) EXPECT_EQ(g.level[0].color[0].at(x, y), 0.0f);
    // The pixels get new seeds, so new values (on the floor: noisy everywhere).
    int floor = 0, differ = 0, seedsDiffer = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        seedsDiffer += prev[Buffer::Seed].at(x, y) != cur[Buffer::Seed].at(x, y);
        if (cur[Buffer::ObjectId].at(x, y) != 1.0f) continue;
        ++floor;
        differ += lum(prev, x, y) != lum(cur, x, y);
      }
    EXPECT_EQ(seedsDiffer, kW * kH);
    EXPECT_GT(differ, floor * 9 / 10);
  };
  check(f0, f1);
  check(f1, f2);
}

TEST(GradientSamples, ASwitchedOffLightGivesGNearOneWhereItLitAndNearZeroElsewhere) {
  // Checklist 20: two lamps over the two halves of a floor, a wall between them; lamp A (left)
  // is off from frame 1 on.
  auto scene = sceneFromJson(R"({
    "frames": 2,
    "objects": [
      {"name": "floor", "shape": "quad", "scale": [8, 1, 4], "material": {"baseColor": 0.7, "specular": 0}},
      {"name": "wall", "shape": "box", "translation": [0, 1.5, 0], "scale": [0.2, 3, 4], "material": {"baseColor": 0.7, "specular": 0}},
      {"name": "lampA", "shape": "quad", "rotation": [180, 0, 0], "scale": [1, 1, 1], "material": {"emissive": 10},
       "animation": [{"frame": 0, "translation": [-2, 2.2, 0], "emission": 1}, {"frame": 1, "emission": 0}]},
      {"name": "lampB", "shape": "quad", "translation": [2, 2.2, 0], "rotation": [180, 0, 0], "material": {"emissive": 10}}
    ],
    "camera": {"position": [0, 6, 5], "target": [0, 0, 0], "fov": 60}
  })");
  Renderer r(scene, tiny(kW, kH));
  r.render(0);
  const Frame f = r.render(1);
  const asvgf::GradientImage g = strataGradient(f);
  int lit = 0, litHigh = 0, other = 0, otherLow = 0;
  for (auto [x, y] : samplePixels(f)) {
    if (f[Buffer::ObjectId].at(x, y) != 1.0f) continue;  // floor samples only
    const float px = f[Buffer::Position].at(x, y, 0);
    const float G = g.level[0].color[0].at(x / 3, y / 3);
    if (px < -0.5f) {
      ++lit;
      litHigh += G > 0.8f;
    } else if (px > 0.5f) {
      ++other;
      otherLow += G < 0.05f;
    }
  }
  ASSERT_GT(lit, 50);
  ASSERT_GT(other, 50);
  // Measured: 100% of the left strata above 0.8 (most exactly 1: no light reaches them now), 100%
  // of the right ones below 0.05 (only lamp A's light bounced over the wall is missing there).
  EXPECT_GE(litHigh, lit * 95 / 100) << litHigh << " of " << lit;
  EXPECT_GE(otherLow, other * 95 / 100) << otherLow << " of " << other;
}

TEST(GradientSamples, FollowCameraMotionAndObjectMotion) {
  // Lambertian surfaces under a sun and a constant sky: radiance leaving a point does not depend
  // on the viewer, so a sample re-shaded at its moved point with its seed reproduces its value
  // unless the projection took it somewhere else. The camera pans; a box floating in the sky
  // moves sideways (nothing for its bounces to hit, so its shading moves with it).
  auto scene = sceneFromJson(R"({
    "frames": 3,
    "objects": [
      {"name": "box", "shape": "box", "scale": 1.2, "material": {"baseColor": [0.8, 0.5, 0.3], "specular": 0},
       "animation": [{"frame": 0, "translation": [-0.6, 0, 0], "rotation": [20, 30, 0]},
                     {"frame": 2, "translation": [0.6, 0, 0], "rotation": [20, 30, 0]}]}
    ],
    "sun": {"direction": [0.3, 1, 0.5], "irradiance": 3},
    "sky": {"color": 0.3},
    "camera": {"keyframes": [{"frame": 0, "position": [-0.3, 0.5, 4], "target": [0, 0, 0]},
                             {"frame": 2, "position": [0.3, 0.6, 4], "target": [0, 0, 0]}], "fov": 40}
  })");
  Renderer r(scene, tiny(kW, kH));
  r.render(0);
  const Frame f = r.render(1);
  const auto samples = samplePixels(f);
  int boxStrata = 0;
  for (int sy = 0; sy < asvgf::strata(kH); ++sy)
    for (int sx = 0; sx < asvgf::strata(kW); ++sx) {
      bool all = true;
      for (int y = 3 * sy; y < std::min(kH, 3 * sy + 3); ++y)
        for (int x = 3 * sx; x < std::min(kW, 3 * sx + 3); ++x) all = all && f[Buffer::ObjectId].at(x, y) == 1.0f;
      boxStrata += all;
    }
  int same = 0;
  for (auto [x, y] : samples) {
    EXPECT_EQ(f[Buffer::ObjectId].at(x, y), 1.0f);  // samples land on the surface they came from
    // Not always bit-exact: the light selection's sun and sky shares follow the scene's bounds,
    // which move with the box by a few ulps.
    same += asvgf::temporalGradient(f[Buffer::GradientPrevious].at(x, y), f[Buffer::GradientCurrent].at(x, y)) < 1e-8f;
  }
  // Nearly every stratum inside the box got a sample, and all but a handful reproduce their value.
  EXPECT_GE(int(samples.size()), boxStrata * 9 / 10);
  EXPECT_GE(same, int(samples.size()) * 98 / 100) << same << " of " << samples.size();
}

TEST(GradientSamples, RandomAccessAndThreadCountGiveTheSameSamples) {
  auto scene = Scene::load("dynamic");
  const RenderSettings s = tiny(48, 30);
  auto sequential = withThreads(1, [&] {
    Renderer r(scene, s);
    r.render(0);
    r.render(1);
    return r.render(2);
  });
  auto direct = withThreads(3, [&] { return Renderer(scene, s).render(2); });  // renders frame 1's source itself
  for (Buffer b : {Buffer::GradientSample, Buffer::GradientPrevious, Buffer::GradientCurrent, Buffer::Color}) {
    const Image &a = sequential[b], &c = direct[b];
    ASSERT_EQ(a.pixels.size(), c.pixels.size());
    EXPECT_EQ(0, std::memcmp(a.pixels.data(), c.pixels.data(), a.pixels.size() * sizeof(float))) << bufferName(b);
  }
  EXPECT_FALSE(samplePixels(direct).empty());
  // --minimal (allBuffers off) and pixel jitter write none.
  RenderSettings minimal = s;
  minimal.allBuffers = false;
  EXPECT_FALSE(Renderer(scene, minimal).render(1).has(Buffer::GradientSample));
  RenderSettings jitter = s;
  jitter.pixelJitter = true;
  EXPECT_FALSE(Renderer(scene, jitter).render(1).has(Buffer::GradientSample));
}

}  // namespace
}  // namespace rtd::render::test
#endif
