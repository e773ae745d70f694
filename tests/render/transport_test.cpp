// Light transport against analytic answers: white furnaces, the cosine law under a sun, and
// unbiasedness (many independent 1-spp frames against a high-spp reference).
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "render/render_test_util.h"

namespace rtd::render::test {
namespace {

struct Stats {
  double mean = 0, variance = 0;  // of the values (sample variance)
  size_t n = 0;
};
Stats stats(const std::vector<double>& v) {
  Stats s;
  s.n = v.size();
  for (double x : v) s.mean += x;
  s.mean /= double(s.n);
  for (double x : v) s.variance += (x - s.mean) * (x - s.mean);
  s.variance /= double(s.n - 1);
  return s;
}

// Inside a closed box whose walls (albedo a, Lambertian) all emit Le, the radiance everywhere
// is Le (1 + a + a^2 + ...) = Le / (1 - a); with maxDepth D the series stops at a^D.
TEST(RenderFurnace, EmissiveEnclosureConvergesToLeOverOneMinusAlbedo) {
  const double albedo = 0.5, le = 1.0;
  const int depth = 40;
  // A negative scale mirrors the box, so its faces' front sides (the emitting sides) face inwards.
  auto scene = sceneFromJson(R"({
    "objects": [{"shape": "box", "scale": [-4, 4, 4],
                 "material": {"baseColor": 0.5, "specular": 0, "emissive": 1.0}}],
    "camera": {"position": [0.3, 0.2, 1.0], "target": [-1, -0.5, -2], "fov": 90}
  })");
  RenderSettings s = tiny(16, 16, 16);
  s.maxDepth = depth;
  Renderer r(scene, s);
  const Frame f = r.render(0);
  std::vector<double> values;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) values.push_back(f[Buffer::Color].at(x, y, c));
  const Stats st = stats(values);
  const double expected = le * (1 - std::pow(albedo, depth + 1)) / (1 - albedo);
  // Channels are identical (grey), so the 3 values of a pixel are one sample: n / 3 samples.
  const double sigma = std::sqrt(st.variance / (double(st.n) / 3.0));
  EXPECT_NEAR(st.mean, expected, 4 * sigma + 1e-4) << "sigma " << sigma;
  EXPECT_LT(sigma, 0.05);  // the test has the power to see a 10% error
}

// A convex Lambertian sphere under a constant sky L reflects exactly a L (it cannot see itself).
// With the sky and the BSDF both cosine-sampled, every MIS-combined sample is close to a L; the
// residual noise comes from the tessellation (shading normal != geometric normal).
TEST(RenderFurnace, DiffuseSphereUnderConstantSkyReflectsAlbedoTimesSky) {
  auto scene = sceneFromJson(R"({
    "objects": [{"shape": "sphere", "material": {"baseColor": 0.6, "specular": 0}}],
    "sky": {"color": 2.0},
    "camera": {"position": [0, 0, 2], "target": [0, 0, 0], "fov": 20}
  })");
  Renderer r(scene, tiny(12, 12, 64));
  const Frame f = r.render(0);
  std::vector<double> values;
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 12; ++x)
      if (f[Buffer::ObjectId].at(x, y) == 1.0f) values.push_back(f[Buffer::Color].at(x, y, 1));
  ASSERT_GT(values.size(), 60u);
  const Stats st = stats(values);
  const double sigma = std::sqrt(st.variance / double(st.n));
  EXPECT_NEAR(st.mean, 0.6 * 2.0, 4 * sigma + 1e-4);
  for (double v : values) EXPECT_NEAR(v, 1.2, 0.1);
}

// A Lambertian plane lit by a directional sun at angle theta: L = a E cos(theta) / pi, exactly
// (the only light is a delta light, and bounced rays escape into a black sky).
TEST(RenderFurnace, DiffusePlaneUnderSunFollowsCosineLaw) {
  for (double thetaDeg : {0.0, 30.0, 60.0, 80.0}) {
    const double th = thetaDeg * 3.14159265358979 / 180.0;
    nlohmann::json j = {
        {"objects", {{{"shape", "quad"}, {"scale", {100, 1, 100}}, {"material", {{"baseColor", 0.7}, {"specular", 0}}}}}},
        {"sun", {{"direction", {std::sin(th), std::cos(th), 0.0}}, {"irradiance", 3.0}}},
        {"camera", {{"position", {0, 2, 0.01}}, {"target", {0, 0, 0}}, {"fov", 30}}}};
    Renderer r(sceneFromJson(j.dump()), tiny(8, 8, 1));
    const Frame f = r.render(0);
    const double expected = 0.7 * 3.0 * std::cos(th) / 3.14159265358979;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) ASSERT_NEAR(f[Buffer::Color].at(x, y, 0), expected, 1e-4 * (1 + expected)) << thetaDeg;
  }
}

// The mean of N independent 1-spp frames (different global seeds) equals a 4096-spp reference
// within Monte Carlo error, on a scene with area light, sky, sun, glossy and mirror surfaces.
TEST(RenderUnbiased, MeanOfOneSppFramesMatchesReference) {
  auto scene = sceneFromJson(R"({
    "objects": [
      {"shape": "quad", "scale": [6, 1, 6], "material": {"baseColor": [0.7, 0.6, 0.5], "roughness": 0.5}},
      {"shape": "quad", "translation": [0, 1.5, -1.5], "rotation": [90, 0, 0], "scale": [6, 1, 3],
       "material": {"baseColor": [0.3, 0.5, 0.7], "specular": 0}},
      {"shape": "sphere", "translation": [-0.5, 0.4, 0], "scale": 0.8, "material": {"baseColor": [0.9, 0.7, 0.4], "metallic": 1, "roughness": 0.3}},
      {"shape": "sphere", "translation": [0.6, 0.35, 0.3], "scale": 0.7, "material": {"mirror": true}},
      {"shape": "quad", "translation": [0.5, 2.0, 0.5], "rotation": [180, 0, 0], "scale": 0.6, "material": {"emissive": 8}}
    ],
    "sky": {"zenith": [0.3, 0.4, 0.6], "horizon": [0.6, 0.6, 0.6], "ground": 0.1},
    "sun": {"direction": [0.3, 0.8, 0.5], "irradiance": 2.0, "angle": 2.0},
    "camera": {"position": [0, 1.0, 3.5], "target": [0, 0.5, 0], "fov": 45}
  })");
  const int w = 12, h = 8, frames = 384, refSpp = 4096;
  std::vector<std::vector<double>> samples(size_t(w) * h);
  for (int k = 0; k < frames; ++k) {
    RenderSettings s = tiny(w, h, 1);
    s.seed = uint32_t(1000 + k);
    s.allBuffers = false;
    Renderer r(scene, s);
    const Frame f = r.render(0);
    for (int i = 0; i < w * h; ++i) samples[i].push_back(luminanceOf(f[Buffer::Color].pixels.data() + 3 * i));
  }
  Renderer ref(scene, tiny(w, h, 1));
  const Image reference = ref.renderReference(0, refSpp);
  EXPECT_EQ(ref.stats().samplesPerPixel, refSpp);
  double sumMean = 0, sumRef = 0, sumVar = 0;
  int outliers = 0;
  for (int i = 0; i < w * h; ++i) {
    const Stats st = stats(samples[i]);
    const double r = luminanceOf(reference.pixels.data() + 3 * i);
    // The reference's error is at most that of refSpp independent samples.
    const double var = st.variance / frames + st.variance / refSpp;
    if (std::fabs(st.mean - r) > 3.5 * std::sqrt(var) + 1e-6) ++outliers;
    sumMean += st.mean;
    sumRef += r;
    sumVar += var;
  }
  EXPECT_NEAR(sumMean, sumRef, 4 * std::sqrt(sumVar)) << "image means differ";
  EXPECT_LE(outliers, 3) << "pixels beyond 3.5 sigma (expected ~0.05 of " << w * h << ")";
}

// Buffer::Emission holds what is noise-free: the primary hit's emission, and an emitter or the
// sky seen through a perfect mirror (times the mirror's Fresnel). A mirror floor reflects an
// emitter that reflects nothing (base colour 0) and the sky: every pixel's radiance is then
// emission, the same in every 1-spp frame, and counted in Direct and Diffuse as the primary
// hit's emission is. The emitter's pixels seen in the mirror carry F Le, F = Schlick(0.9, cos).
TEST(RenderEmission, EmitterAndSkySeenInAPerfectMirrorAreEmission) {
  auto scene = sceneFromJson(R"({
    "objects": [
      {"shape": "quad", "scale": 40, "material": {"baseColor": 0.9, "mirror": true}},
      {"shape": "quad", "translation": [0, 1, -3], "rotation": [90, 0, 0], "scale": [4, 1, 2],
       "material": {"baseColor": 0, "specular": 0, "emissive": [3, 2, 1]}}
    ],
    "sky": {"color": [0.2, 0.4, 0.8]}, "camera": {"position": [0, 1, 3], "target": [0, 0.2, -1], "fov": 60}
  })");
  const int w = 32, h = 24;
  std::vector<Frame> frames;
  for (uint32_t seed : {1u, 2u}) {
    RenderSettings s = tiny(w, h);
    s.seed = seed;
    frames.push_back(Renderer(scene, s).render(0));
  }
  const Frame& f = frames[0];
  int mirrorEmitter = 0, mirrorSky = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float e = f[Buffer::Emission].at(x, y, c);
        ASSERT_EQ(f[Buffer::Color].at(x, y, c), e) << x << "," << y;
        ASSERT_EQ(frames[1][Buffer::Emission].at(x, y, c), e) << x << "," << y << ": not noise-free";
        EXPECT_EQ(f[Buffer::Direct].at(x, y, c), e);
        EXPECT_EQ(f[Buffer::Diffuse].at(x, y, c), e);
        EXPECT_EQ(f[Buffer::Specular].at(x, y, c), 0.0f);
      }
      if (f[Buffer::ObjectId].at(x, y) != 1.0f) continue;  // the mirror floor only
      const Vec d = norm(sub(px3(f[Buffer::Position], x, y), {0, 1, 3}));
      const double cosine = -d[1];  // the floor's normal is +y
      const double fresnel = 0.9 + 0.1 * std::pow(1 - cosine, 5);
      const Vec e = px3(f[Buffer::Emission], x, y);
      if (e[0] > 1.0) {  // the emitter's reflection
        ++mirrorEmitter;
        EXPECT_NEAR(e[0], 3 * fresnel, 1e-4);
        EXPECT_NEAR(e[1], 2 * fresnel, 1e-4);
        EXPECT_NEAR(e[2], 1 * fresnel, 1e-4);
      } else {
        ++mirrorSky;
        EXPECT_NEAR(e[2], 0.8 * fresnel, 1e-4);
      }
    }
  EXPECT_GT(mirrorEmitter, 20);
  EXPECT_GT(mirrorSky, 20);
}

}  // namespace
}  // namespace rtd::render::test
#endif
