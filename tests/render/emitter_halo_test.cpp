// Emitter halo (issue 12): a lamp on the ceiling of the renderer's Cornell box, camera still.
// After 16 frames at 1 spp, the error of the ceiling pixels next to the lamp (1 to 3 pixels from
// it) is compared with the error of the ceiling further away (6 pixels or more), for svgf and
// bmfr: light bleeding from the emitter into its surroundings shows as a larger error next to
// it. The error is the mean |difference| of display luma (Reinhard, sRGB) to a 256-spp
// reference; emitter pixels themselves are excluded (their emission is added back exactly).
// Measured (96x54, default settings, display-domain TAA): svgf 0.0247 next to the lamp vs
// 0.0197 elsewhere (ratio 1.25, bias -0.023 vs +0.012; excludeEmitters=true: 1.40, bias -0.026
// vs +0.010), bmfr (excludeEmitters on by default) 0.0250 vs 0.0289 (ratio 0.86, bias +0.023 vs
// -0.014; off: 0.83). Asserted: below 2x. What remains for svgf is not light from the lamp
// (the exclusion takes the lamp's pixels out of the filter exactly: tests/passes/emitters_test.cpp)
// but the a-trous levels flattening the ceiling's own illumination, which peaks around the lamp
// (display luma 0.33-0.37 next to it, 0.18-0.25 at the ceiling's edges): too dark at the peak,
// too bright at the edges (docs/methods/svgf.md, "Emitters").
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "render/render_test_util.h"
#include "rtd/rtd.h"
#include "support/ceiling_halo.h"

namespace rtd::render::test {
namespace {

std::string stillCornell() {
  std::string s = Scene::builtinDescription("cornell");
  // Both camera keys at the first one's position: a static scene.
  const std::string moving = "\"position\": [0.35, 1, 3.9]", still = "\"position\": [-0.35, 1, 3.9]";
  const size_t at = s.find(moving);
  if (at != std::string::npos) s.replace(at, moving.size(), still);
  return s;
}

TEST(EmitterHalo, CeilingNextToTheLampIsNoWorseThanElsewhere) {
  RenderSettings rs;
  rs.width = 96;
  rs.height = 54;
  auto scene = sceneFromJson(stillCornell());
  Renderer renderer(scene, rs);
  constexpr int kFrames = 16;
  std::vector<Frame> frames;
  for (int t = 0; t < kFrames; ++t) frames.push_back(renderer.render(t));
  const Image reference = renderer.renderReference(kFrames - 1, 256);
  const Frame& last = frames.back();
  ASSERT_FALSE(last[Buffer::Emission].pixels.empty());
  const int w = rs.width, h = rs.height;
  // Ceiling: downward normal, world height 2.
  auto ceiling = [&](int x, int y) {
    return last[Buffer::Normal].at(x, y, 1) < -0.9f && last[Buffer::Position].at(x, y, 1) > 1.99f;
  };
  for (const char* method : {"svgf", "bmfr"}) {
    auto d = Device::create({.backend = Backend::Cpu, .threads = 2})->createDenoiser(method);
    Image out(w, h, 3);
    for (const Frame& f : frames) d->denoise(f.inputs(), out.view());
    const rtd::test::CeilingHalo r = rtd::test::ceilingHalo(last, out, reference, ceiling);
    ASSERT_GE(r.lampPixels, 12) << "the lamp is visible";
    ASSERT_GT(r.nNear, 10);
    ASSERT_GT(r.nFar, 10);
    r.print(method);
    RecordProperty(std::string(method) + "_ratio", std::to_string(r.ratio()));
    EXPECT_LT(r.near, 2.0 * r.far) << method;
  }
  // The renderer's lamp has a reflectance (albedo = its base colour, 1): SVGF's default keeps it
  // in the filter, so its output is bit for bit that with no emitter at all (a threshold above
  // the lamp's emission), and the quality tables of docs/methods/svgf.md stay as measured. The
  // Blender lamp, whose albedo is its emission, leaves it (tests/passes/emitter_halo_blender_test.cpp).
  Image plain(w, h, 3), noEmitter(w, h, 3);
  {
    auto d = Device::create({.backend = Backend::Cpu, .threads = 2})->createDenoiser("svgf");
    auto e = Device::create({.backend = Backend::Cpu, .threads = 2})->createDenoiser("svgf");
    e->set("emitterThreshold", "1e9");
    for (const Frame& f : frames) {
      d->denoise(f.inputs(), plain.view());
      e->denoise(f.inputs(), noEmitter.view());
    }
  }
  EXPECT_EQ(std::memcmp(plain.pixels.data(), noEmitter.pixels.data(), plain.pixels.size() * sizeof(float)), 0);
}

}  // namespace
}  // namespace rtd::render::test
#endif
