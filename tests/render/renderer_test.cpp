// Renderer behaviour: determinism across thread counts, seed re-use (A-SVGF re-shading), sparse
// blue-noise masks, glTF loading, errors naming file and field, and the `render` CLI with its
// reference cache and stereo layout.
#ifdef HAVE_RTDENOISE_RENDER
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "render/render_test_util.h"
#include "rtd/error.h"

namespace rtd::render::test {
namespace {

namespace fs = std::filesystem;

bool sameFrames(const Frame& a, const Frame& b, std::string& which) {
  for (int i = 0; i < kBufferCount; ++i) {
    const Image &x = a.buffers[i], &y = b.buffers[i];
    // Bitwise (NaN payloads and -0 included); memcmp of an empty buffer's null data is undefined.
    if (x.pixels.size() != y.pixels.size() ||
        (!x.pixels.empty() && std::memcmp(x.pixels.data(), y.pixels.data(), x.pixels.size() * sizeof(float)) != 0)) {
      which = std::string(bufferName(Buffer(i)));
      return false;
    }
  }
  return true;
}

TEST(RenderDeterminism, BitIdenticalForAnyThreadCount) {
  auto scene = Scene::load("glossy");
  RenderSettings s = tiny(40, 24, 2);
  s.pixelJitter = true;
  auto renderWith = [&](int threads) {
    return withThreads(threads, [&] {
      Renderer r(scene, s);
      return r.render(3);
    });
  };
  const Frame one = renderWith(1), two = renderWith(2), four = renderWith(4);
  std::string which;
  EXPECT_TRUE(sameFrames(one, two, which)) << "buffer " << which;
  EXPECT_TRUE(sameFrames(one, four, which)) << "buffer " << which;
  const Image refA = withThreads(1, [&] { return Renderer(scene, s).renderReference(3, 8); });
  const Image refB = withThreads(3, [&] { return Renderer(scene, s).renderReference(3, 8); });
  EXPECT_EQ(0, std::memcmp(refA.pixels.data(), refB.pixels.data(), refA.pixels.size() * sizeof(float)));
}

TEST(RenderDeterminism, SeedReuseReproducesThePixelExactly) {
  // Static camera and scene: a seed of frame 0 re-shaded in frame 1 gives frame 0's value.
  auto scene = sceneFromJson(R"({
    "frames": 2,
    "objects": [
      {"shape": "quad", "scale": 6, "material": {"baseColor": 0.7, "roughness": 0.4}},
      {"shape": "sphere", "translation": [0, 0.5, 0], "material": {"baseColor": [0.8, 0.3, 0.2], "roughness": 0.2}}
    ],
    "sky": {"zenith": 0.5, "horizon": 1.0, "ground": 0.2},
    "sun": {"direction": [0.3, 1, 0.2], "irradiance": 2, "angle": 1},
    "camera": {"position": [0, 1.5, 3], "target": [0, 0.4, 0]}
  })");
  Renderer r(scene, tiny(16, 12));
  const Frame f0 = r.render(0), f1 = r.render(1);
  int differentWithOtherSeed = 0;
  for (int y = 0; y < 12; y += 1)
    for (int x = 0; x < 16; x += 3) {
      const uint32_t seed = uint32_t(f0[Buffer::Seed].at(x, y));
      EXPECT_EQ(float(seed), f0[Buffer::Seed].at(x, y));  // 24-bit seeds are exact in float
      EXPECT_LT(seed, kSeedLimit);
      EXPECT_EQ(seed, r.pixelSeed(0, x, y));
      const auto same = r.shadePixel(0, x, y, seed);
      const auto later = r.shadePixel(1, x, y, seed);
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(same[c], f0[Buffer::Color].at(x, y, c)) << x << "," << y;
        EXPECT_EQ(later[c], f0[Buffer::Color].at(x, y, c)) << x << "," << y;
      }
      const auto other = r.shadePixel(1, x, y, uint32_t(f1[Buffer::Seed].at(x, y)));
      EXPECT_EQ(other[0], f1[Buffer::Color].at(x, y, 0));
      if (other[0] != same[0]) ++differentWithOtherSeed;
    }
  EXPECT_GT(differentWithOtherSeed, 20);  // seeds really drive the random numbers
}

TEST(RenderReference, ProgressivePassesStopAtTheTimeBudget) {
  auto scene = Scene::load("cornell");
  Renderer r(scene, tiny(4, 4));
  // 2^20 samples would take many seconds; a 50 ms budget stops after a whole pass of the
  // doubling sequence 1, 2, 4, ..., so the count taken is 2^k - 1.
  const Image img = r.renderReference(0, 1 << 20, 0.05);
  const int taken = r.stats().samplesPerPixel;
  EXPECT_GE(taken, 1);
  EXPECT_LT(taken, 1 << 20);
  EXPECT_EQ((taken + 1) & taken, 0) << taken;
  for (float v : img.pixels) EXPECT_TRUE(std::isfinite(v) && v >= 0);
}

TEST(RenderSparse, RotatingBlueNoiseMaskCoversEveryPixelOncePerCycle) {
  auto scene = Scene::load("cornell");
  RenderSettings s = tiny(64, 64);
  s.sampleFraction = 0.125f;
  Renderer r(scene, s);
  std::vector<int> count(64 * 64, 0);
  for (int k = 0; k < 8; ++k) {
    const Frame f = r.render(k);
    int traced = 0, clumped = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const bool m = f[Buffer::SampleMask].at(x, y) == 1.0f;
        EXPECT_EQ(m, r.sampleMask(k, x, y));
        if (!m) {
          for (int c = 0; c < 3; ++c) EXPECT_EQ(f[Buffer::Color].at(x, y, c), 0.0f);
          EXPECT_GT(f[Buffer::Depth].at(x, y), 0.0f);  // features stay complete
          continue;
        }
        ++traced;
        ++count[y * 64 + x];
        const bool neighbour = (x > 0 && r.sampleMask(k, x - 1, y)) || (x < 63 && r.sampleMask(k, x + 1, y)) ||
                               (y > 0 && r.sampleMask(k, x, y - 1)) || (y < 63 && r.sampleMask(k, x, y + 1));
        clumped += neighbour;
      }
    EXPECT_EQ(traced, 512);
    // White noise at 1/8 gives a traced 4-neighbour to 41% of the samples; blue noise far fewer.
    EXPECT_LT(clumped, traced / 10) << "frame " << k;
  }
  for (int c : count) ASSERT_EQ(c, 1);
}

std::string base64(const std::vector<unsigned char>& data) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    const uint32_t n = (uint32_t(data[i]) << 16) | (i + 1 < data.size() ? uint32_t(data[i + 1]) << 8 : 0) |
                       (i + 2 < data.size() ? data[i + 2] : 0);
    out += t[(n >> 18) & 63];
    out += t[(n >> 12) & 63];
    out += i + 1 < data.size() ? t[(n >> 6) & 63] : '=';
    out += i + 2 < data.size() ? t[n & 63] : '=';
  }
  return out;
}

/// A glTF 2.0 file: a 2 x 2 quad in XZ under a node translated to y = 0.5, a metallic-roughness
/// material, and a camera node 3 units up looking down.
fs::path writeQuadGltf(const fs::path& dir) {
  std::vector<unsigned char> bytes;
  auto push = [&](const void* p, size_t n) { bytes.insert(bytes.end(), (const unsigned char*)p, (const unsigned char*)p + n); };
  const float pos[] = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1};
  const float nrm[] = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  const uint16_t idx[] = {0, 2, 1, 0, 3, 2};
  push(pos, sizeof pos);
  push(nrm, sizeof nrm);
  push(idx, sizeof idx);
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 1}}}}},
      {"nodes", {{{"mesh", 0}, {"translation", {0, 0.5, 0}}, {"name", "quad"}},
                 {{"camera", 0}, {"translation", {0, 3, 0}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}}}},
      {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.01}, {"aspectRatio", 1.0}}}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}, {"material", 0}}}}}}},
      {"materials", {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.3, 0.6, 0.9, 1.0}}, {"metallicFactor", 0.25},
                                                {"roughnessFactor", 0.75}}}}}},
      {"buffers", {{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 48}},
                       {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 12}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                      {"min", {-1, 0, -1}}, {"max", {1, 0, 1}}},
                     {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                     {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}}};
  const fs::path file = dir / "quad.gltf";
  std::ofstream(file) << j.dump(1);
  return file;
}

TEST(RenderGltf, LoadsMeshMaterialNodeTransformAndCamera) {
  const fs::path dir = tempDir("gltf");
  const fs::path file = writeQuadGltf(dir);
  auto scene = Scene::load(file.string());
  Renderer r(scene, tiny(8, 8));
  const Frame f = r.render(0);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      ASSERT_EQ(f[Buffer::ObjectId].at(x, y), 1.0f) << "the quad fills the glTF camera's view";
      EXPECT_NEAR(f[Buffer::Albedo].at(x, y, 0), 0.3, 1e-6);
      EXPECT_NEAR(f[Buffer::Albedo].at(x, y, 1), 0.6, 1e-6);
      EXPECT_NEAR(f[Buffer::Albedo].at(x, y, 2), 0.9, 1e-6);
      EXPECT_NEAR(f[Buffer::Metalness].at(x, y), 0.25, 1e-6);
      EXPECT_NEAR(f[Buffer::Roughness].at(x, y), 0.75, 1e-6);
      EXPECT_NEAR(f[Buffer::Position].at(x, y, 1), 0.5, 1e-5);  // node translation
      EXPECT_NEAR(f[Buffer::Depth].at(x, y), 2.5, 1e-4);        // camera node at y = 3
      EXPECT_NEAR(f[Buffer::Normal].at(x, y, 1), 1.0, 1e-5);
    }
  // The camera's vertical field of view is the glTF yfov: projection[5] = 1 / tan(yfov / 2).
  EXPECT_NEAR(f.camera.projection[5], 1.0 / std::tan(0.25), 1e-4);
  // A JSON description can place and animate glTF nodes by name.
  std::ofstream(dir / "anim.json") << R"({"gltf": "quad.gltf", "frames": 3,
      "animations": {"quad": [{"frame": 0, "translation": [0, 0, 0]}, {"frame": 2, "translation": [0, 1, 0]}]}})";
  auto animated = Scene::load((dir / "anim.json").string());
  Renderer ra(animated, tiny(8, 8));
  EXPECT_NEAR(ra.render(1)[Buffer::Position].at(4, 4, 1), 1.0, 1e-5);  // 0.5 + 0.5 at frame 1
  fs::remove_all(dir);
}

std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RenderErrors, BadScenesAndSettingsNameTheFileAndField) {
  using ::testing::HasSubstr;
  EXPECT_THAT(errorOf([] { Scene::load("no_such_scene.json"); }), HasSubstr("no_such_scene.json"));
  EXPECT_THAT(errorOf([] { Scene::load("no_such_builtin"); }), HasSubstr("built-in"));
  EXPECT_THAT(errorOf([] { sceneFromJson(R"({"objects": [{"shape": "cone"}]})"); }),
              testing::AllOf(HasSubstr("test.json"), HasSubstr("objects[0].shape"), HasSubstr("cone")));
  EXPECT_THAT(errorOf([] { sceneFromJson(R"({"frames": "ten", "sky": {"color": 1}})"); }), HasSubstr("'frames'"));
  EXPECT_THAT(errorOf([] { sceneFromJson(R"({"sky": {"colour": 1}})"); }), HasSubstr("sky.colour"));
  EXPECT_THAT(errorOf([] { sceneFromJson(R"({"objects": [{"shape": "box", "material": {"roughness": 2}}]})"); }),
              HasSubstr("objects[0].material.roughness"));
  EXPECT_THAT(errorOf([] { sceneFromJson(R"({"sky": {"color": 1}, "camera": {"keyframes": [{"frame": 2}, {"frame": 1}]}})"); }),
              HasSubstr("camera.keyframes[1].frame"));
  EXPECT_THAT(errorOf([] { sceneFromJson("{not json"); }), HasSubstr("not valid JSON"));
  auto scene = Scene::load("cornell");
  EXPECT_THAT(errorOf([&] { Renderer(scene, tiny(8, 8, 0)); }), HasSubstr("'spp'"));
  EXPECT_THAT(errorOf([&] {
                RenderSettings s = tiny(8, 8);
                s.sampleFraction = 0;
                Renderer(scene, s);
              }),
              HasSubstr("sampleFraction"));
  const fs::path dir = tempDir("badgltf");
  std::ofstream(dir / "broken.gltf") << R"({"asset": {"version": "2.0"}, "meshes": [)";
  EXPECT_THAT(errorOf([&] { Scene::load((dir / "broken.gltf").string()); }), HasSubstr("broken.gltf"));
  fs::remove_all(dir);
}

TEST(RenderCli, WritesSequenceAndCachedReferences) {
  const fs::path dir = tempDir("cli");
  const std::string common = "render --scene dynamic --frames 2 --size 16x8 --reference-spp 8 --reference-cache " +
                             (dir / "cache").string();
  std::string out;
  ASSERT_EQ(runCli(common + " --output " + (dir / "a").string(), out), 0) << out;
  ASSERT_EQ(runCli(common + " --output " + (dir / "b").string(), out), 0) << out;
  auto seq = SequenceReader::open(dir / "a");
  EXPECT_EQ(seq->frameCount(), 2);
  const auto buffers = seq->buffers();
  for (Buffer b : {Buffer::Color, Buffer::Motion, Buffer::Seed, Buffer::ReflectedPosition, Buffer::SampleMask})
    EXPECT_NE(std::find(buffers.begin(), buffers.end(), b), buffers.end()) << bufferName(b);
  auto metaOf = [](const fs::path& p) { return nlohmann::json::parse(std::ifstream(p / "render.json")); };
  EXPECT_EQ(metaOf(dir / "a")["reference"]["samplesTaken"], nlohmann::json({8, 8}));
  EXPECT_EQ(metaOf(dir / "b")["reference"]["samplesTaken"], nlohmann::json({-1, -1}));  // from the cache
  auto refA = SequenceReader::open(dir / "a" / "reference"), refB = SequenceReader::open(dir / "b" / "reference");
  const Frame fa = refA->read(1), fb = refB->read(1);
  ASSERT_TRUE(fa.has(Buffer::Color));
  EXPECT_EQ(fa[Buffer::Color].pixels, fb[Buffer::Color].pixels);
  // The cached reference is the library's reference for that frame.
  auto scene = Scene::load("dynamic");
  Renderer r(scene, tiny(16, 8));
  EXPECT_EQ(r.renderReference(1, 8).pixels, fa[Buffer::Color].pixels);
  fs::remove_all(dir);
}

TEST(RenderCli, StereoLayoutAndBadInputExitCode) {
  const fs::path dir = tempDir("stereo");
  std::string out;
  ASSERT_EQ(runCli("render --scene cornell --frames 1 --size 16x8 --stereo --eye-distance 0.2 --no-reference-cache --output " +
                       (dir / "s").string(),
                   out),
            0)
      << out;
  for (const char* eye : {"left", "right"}) {
    EXPECT_EQ(SequenceReader::open(dir / "s" / eye)->frameCount(), 1);
    const auto meta = nlohmann::json::parse(std::ifstream(dir / "s" / eye / "render.json"));
    EXPECT_EQ(meta["eye"], eye);
    EXPECT_NEAR(meta["eyeDistance"].get<double>(), 0.2, 1e-6);
  }
  std::ofstream(dir / "bad.json") << R"({"objects": [{"shape": "box", "material": {"metallic": "yes"}}]})";
  EXPECT_NE(runCli("render --scene " + (dir / "bad.json").string() + " --output " + (dir / "x").string(), out), 0);
  EXPECT_THAT(out, testing::AllOf(testing::HasSubstr("bad.json"), testing::HasSubstr("objects[0].material.metallic")));
  EXPECT_NE(runCli("render --scene cornell --spp 0 --output " + (dir / "y").string(), out), 0);
  EXPECT_THAT(out, testing::HasSubstr("spp"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtd::render::test
#endif
