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

#include "passes/tonemap.h"
#include "render/render_test_util.h"
#include "rtd/rtd.h"

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

double displayLuma(const Image& img, int x, int y) {
  auto d = [&](int c) { return double(tonemap::toneMapToSrgb(img.at(x, y, c), tonemap::Operator::Reinhard, 1.0f)); };
  return tonemap::luminance(float(d(0)), float(d(1)), float(d(2)));
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
  // Ceiling: downward normal, world height 2; the lamp: its emission.
  auto emitter = [&](int x, int y) { return last[Buffer::Emission].at(x, y, 0) > 0.0f; };
  auto ceiling = [&](int x, int y) {
    return last[Buffer::Normal].at(x, y, 1) < -0.9f && last[Buffer::Position].at(x, y, 1) > 1.99f && !emitter(x, y);
  };
  auto distance = [&](int x, int y) {  // Chebyshev distance to the nearest emitter pixel, capped
    for (int r = 1; r <= 8; ++r)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx >= 0 && qy >= 0 && qx < w && qy < h && emitter(qx, qy)) return r;
        }
    return 9;
  };
  int lamp = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) lamp += emitter(x, y);
  ASSERT_GE(lamp, 12) << "the lamp is visible";

  for (const char* method : {"svgf", "bmfr"}) {
    auto d = Device::create({.backend = Backend::Cpu, .threads = 2})->createDenoiser(method);
    Image out(w, h, 3);
    for (const Frame& f : frames) d->denoise(f.inputs(), out.view());
    double near = 0, far = 0, nearBias = 0, farBias = 0;
    int nNear = 0, nFar = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (!ceiling(x, y)) continue;
        const int r = distance(x, y);
        const double e = displayLuma(out, x, y) - displayLuma(reference, x, y);
        if (r <= 3) { near += std::abs(e), nearBias += e, ++nNear; }
        if (r >= 6) { far += std::abs(e), farBias += e, ++nFar; }
      }
    ASSERT_GT(nNear, 10);
    ASSERT_GT(nFar, 10);
    near /= nNear, far /= nFar, nearBias /= nNear, farBias /= nFar;
    std::printf("%s: ceiling next to the lamp |err| %.4f (bias %+.4f, %d px), elsewhere %.4f (bias %+.4f, %d px), ratio %.2f\n",
                method, near, nearBias, nNear, far, farBias, nFar, near / far);
    RecordProperty(std::string(method) + "_ratio", std::to_string(near / far));
    EXPECT_LT(near, 2.0 * far) << method;
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
