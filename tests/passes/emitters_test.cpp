// Emitter exclusion (EmitterSettings, rtd/methods/emitters.h; issue 12, the emitter halo), for
// svgf and bmfr on the CPU. With it on, emitter pixels weigh 0 as neighbours and take none: on
// a still view the output of every other pixel does not depend on the emitters' radiance at
// all, and an emitter's output does not depend on its surroundings' (bit for bit; TAA off: its
// clamp box reads the 3x3 neighbourhood and is not part of the exclusion; SVGF's variance
// prefilter off, see kCases). Off, both do (which
// shows the comparison can fail). A frame without emitters gives the same output bit for bit
// with the setting on and off. The halo itself on a path-traced lamp: tests/render/emitter_halo_test.cpp.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

constexpr int kEmittersW = 64, kEmittersH = 48;
// The lamp: a screen rectangle (over the wall and the sphere of the synthetic scene: the
// exclusion does not care which surface it is on).
bool lamp(int x, int y) { return x >= 22 && x < 38 && y >= 8 && y < 18; }

// A still view of the synthetic scene with a lamp of emission 8 whose reflected light is
// `lampLight` times the scene's noisy radiance there, the rest scaled by `restScale`.
// `lampAlbedo` > 0: the lamp's albedo (Cycles writes an emissive surface's emission there).
std::vector<Frame> stillFramesWithLamp(int count, float lampLight, float restScale, bool emissionBuffer = true,
                                       float lampAlbedo = 0.0f) {
  synthetic::Scene scene;
  scene.width = kEmittersW;
  scene.height = kEmittersH;
  scene.cameraSpeed = 0.0f;
  scene.gradientSamples = false;
  std::vector<Frame> frames;
  for (int i = 0; i < count; ++i) {
    Frame f = synthetic::makeFrame(scene, i);
    // Exactly still: the scene's motion of a still camera is 0 only to rounding, and sub-pixel
    // reprojection taps would mix a little history across the lamp's border (not excluded).
    f[Buffer::Motion] = Image(kEmittersW, kEmittersH, 2, 0.0f);
    if (emissionBuffer) f[Buffer::Emission] = Image(kEmittersW, kEmittersH, 3, 0.0f);
    for (int y = 0; y < kEmittersH; ++y)
      for (int x = 0; x < kEmittersW; ++x)
        for (int c = 0; c < 3; ++c) {
          float& v = f[Buffer::Color].at(x, y, c);
          if (!emissionBuffer || !lamp(x, y)) {
            v *= restScale;
            continue;
          }
          f[Buffer::Emission].at(x, y, c) = 8.0f;
          v = 8.0f + lampLight * v;
          if (lampAlbedo > 0.0f) f[Buffer::Albedo].at(x, y, c) = lampAlbedo;
        }
    frames.push_back(std::move(f));
  }
  return frames;
}

Image run(const std::string& method, const std::vector<std::string>& settings, const std::vector<Frame>& frames) {
  auto d = Device::create({.backend = Backend::Cpu, .threads = 2})->createDenoiser(method);
  for (const auto& s : settings) {
    const auto eq = s.find('=');
    d->set(s.substr(0, eq), s.substr(eq + 1));
  }
  Image out(kEmittersW, kEmittersH, 3);
  for (const Frame& f : frames) d->denoise(f.inputs(), out.view());
  return out;
}

// Pixels (inside or outside the lamp) whose outputs differ in any bit.
int differing(const Image& a, const Image& b, bool insideLamp) {
  int n = 0;
  for (int y = 0; y < kEmittersH; ++y)
    for (int x = 0; x < kEmittersW; ++x) {
      if (lamp(x, y) != insideLamp) continue;
      bool same = true;
      for (int c = 0; c < 3; ++c) {
        const float u = a.at(x, y, c), v = b.at(x, y, c);
        same &= std::memcmp(&u, &v, sizeof(float)) == 0;
      }
      n += !same;
    }
  return n;
}

struct Case {
  const char* method;
  std::vector<std::string> settings;
};

// SVGF without the 3x3 Gaussian of the variance (Schied Eq. 5): that prefilter reads the
// neighbours' variance unweighted, so a ring pixel's w_l bandwidth (not its light) still
// depends on the lamp's variance (docs/methods/svgf.md, "Emitters").
const std::vector<Case> kCases = {
    {"svgf", {"excludeEmitters=true", "variancePrefilter=off", "taa=false"}},
    {"svgf", {"variant=dundr", "excludeEmitters=true", "variancePrefilter=off", "taa=false"}},
    {"bmfr", {"taa=false"}},
    {"bmfr", {"samplesPerBlock=36", "taa=false"}},
};

TEST(EmitterExclusion, NeighboursIgnoreTheEmitterAndTheEmitterItsNeighbours) {
  const auto base = stillFramesWithLamp(6, 0.1f, 1.0f);
  const auto brightLamp = stillFramesWithLamp(6, 3.0f, 1.0f);   // other light on the lamp only
  const auto brightRest = stillFramesWithLamp(6, 0.1f, 2.0f);   // other light off the lamp only
  for (const Case& c : kCases) {
    std::string what = c.method;
    for (const auto& s : c.settings) what += " " + s;
    const Image a = run(c.method, c.settings, base);
    EXPECT_EQ(differing(a, run(c.method, c.settings, brightLamp), false), 0) << what << ": the lamp leaks out";
    EXPECT_EQ(differing(a, run(c.method, c.settings, brightRest), true), 0) << what << ": the lamp takes its neighbours' light";
    // Off, the filter mixes them: many pixels around the lamp change.
    std::vector<std::string> off = c.settings;
    off.push_back("excludeEmitters=false");
    const Image b = run(c.method, off, base);
    EXPECT_GT(differing(b, run(c.method, off, brightLamp), false), 40) << what << ", off";
    EXPECT_GT(differing(b, run(c.method, off, brightRest), true), 40) << what << ", off";
  }
}

// With excludeEmitters off (SVGF's default), an emitter whose albedo is no reflectance (above 1:
// Cycles writes an emissive surface's emission as its Denoising Albedo, tests/fixtures/
// blender_lamp) still leaves the a-trous guide, as the sky does: the output off the lamp does not
// depend on the lamp's light, bit for bit. A lamp with a reflectance (albedo 1, as the
// renderer's) stays in the filter, and so does the reflectanceless one when its emission is not
// above the threshold. BMFR's fits follow excludeEmitters alone.
TEST(EmitterExclusion, SvgfLeavesEmittersWithoutAReflectanceOut) {
  const std::vector<std::string> off = {"variancePrefilter=off", "taa=false"};  // excludeEmitters: default (off)
  for (const char* variant : {"schied", "dundr"}) {
    std::vector<std::string> s = {std::string("variant=") + variant};  // first: a preset resets the others
    s.insert(s.end(), off.begin(), off.end());
    const Image a = run("svgf", s, stillFramesWithLamp(6, 0.1f, 1.0f, true, 8.0f));
    EXPECT_EQ(differing(a, run("svgf", s, stillFramesWithLamp(6, 3.0f, 1.0f, true, 8.0f)), false), 0) << variant;
    const Image b = run("svgf", s, stillFramesWithLamp(6, 0.1f, 1.0f, true, 1.0f));
    EXPECT_GT(differing(b, run("svgf", s, stillFramesWithLamp(6, 3.0f, 1.0f, true, 1.0f)), false), 40) << variant;
    std::vector<std::string> high = s;
    high.push_back("emitterThreshold=8");
    const Image c = run("svgf", high, stillFramesWithLamp(6, 0.1f, 1.0f, true, 8.0f));
    EXPECT_GT(differing(c, run("svgf", high, stillFramesWithLamp(6, 3.0f, 1.0f, true, 8.0f)), false), 40) << variant;
  }
  const Image a = run("bmfr", {"excludeEmitters=false", "taa=false"}, stillFramesWithLamp(6, 0.1f, 1.0f, true, 8.0f));
  const Image b = run("bmfr", {"excludeEmitters=false", "taa=false"}, stillFramesWithLamp(6, 3.0f, 1.0f, true, 8.0f));
  EXPECT_GT(differing(a, b, false), 40) << "bmfr";
}

// Without emitters the setting changes nothing, bit for bit: frames without Buffer::Emission,
// with an all-zero one, and with a lamp whose emission is below the threshold (which is then
// no emitter). A moving camera, TAA on.
TEST(EmitterExclusion, WithoutEmittersTheOutputIsBitIdentical) {
  synthetic::Scene scene;
  scene.width = kEmittersW;
  scene.height = kEmittersH;
  std::vector<Frame> plain, zero;
  for (int i = 0; i < 5; ++i) {
    plain.push_back(synthetic::makeFrame(scene, i));
    zero.push_back(plain.back());
    zero.back()[Buffer::Emission] = Image(kEmittersW, kEmittersH, 3, 0.0f);
  }
  const auto lampAtThreshold = stillFramesWithLamp(5, 0.1f, 1.0f);
  for (const char* method : {"svgf", "bmfr"}) {
    for (const auto* frames : {&plain, &zero}) {
      const Image on = run(method, {"excludeEmitters=true"}, *frames), off = run(method, {"excludeEmitters=false"}, *frames);
      EXPECT_EQ(differing(on, off, false) + differing(on, off, true), 0) << method;
    }
    const Image on = run(method, {"excludeEmitters=true", "emitterThreshold=8"}, lampAtThreshold);
    const Image off = run(method, {"excludeEmitters=false"}, lampAtThreshold);
    EXPECT_EQ(differing(on, off, false) + differing(on, off, true), 0) << method << ", emission at the threshold";
    // Just below it the lamp is an emitter again.
    const Image below = run(method, {"excludeEmitters=true", "emitterThreshold=7.99"}, lampAtThreshold);
    EXPECT_GT(differing(below, off, false), 0) << method;
  }
}

}  // namespace
}  // namespace rtd
