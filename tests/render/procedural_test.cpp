// The procedural scene generator and `rtdenoise dataset`: deterministic for a seed (the scene
// text, and the data set's training cache byte for byte, on 1 or 2 threads), different for
// another seed; every scene loads and is lit; the seeds cover rooms and open grounds, glossy,
// metal and mirror materials, textures and motion; the cache matches the sequence it came from.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "render/render_test_util.h"
#include "rtd/error.h"
#include "rtd/render/procedural.h"

namespace rtd::render::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Procedural, SameSeedSameSceneOtherSeedOtherScene) {
  EXPECT_EQ(proceduralSceneJson(7), proceduralSceneJson(7));
  EXPECT_NE(proceduralSceneJson(7), proceduralSceneJson(8));
  const json j = json::parse(proceduralSceneJson(7, {5, 64, 48}));
  EXPECT_EQ(j["frames"], 5);
  EXPECT_EQ(j["resolution"], json::array({64, 48}));
}

TEST(Procedural, ScenesLoadAreLitAndCoverTheMaterialsAndLights) {
  int rooms = 0, suns = 0, glossy = 0, metals = 0, mirrors = 0, patterns = 0, moving = 0;
  for (uint32_t seed = 0; seed < 40; ++seed) {
    const std::string text = proceduralSceneJson(seed, {4, 32, 32});
    ASSERT_NO_THROW(sceneFromJson(text)) << "seed " << seed;
    const json j = json::parse(text);
    bool lamp = false;
    for (const auto& [name, m] : j["materials"].items()) {
      lamp |= m.contains("emissive");
      const bool metal = m.value("metallic", 0) == 1;
      mirrors += m.value("mirror", false);
      metals += metal;
      glossy += !metal && !m.contains("mirror") && m.value("roughness", 1.0) < 0.5;
      patterns += m.contains("pattern");
    }
    for (const auto& o : j["objects"]) moving += o.contains("animation");
    const bool sun = j.contains("sun");
    rooms += !sun;
    suns += sun;
    EXPECT_TRUE(lamp || sun) << "seed " << seed << " has no light";
  }
  EXPECT_GT(rooms, 10);
  EXPECT_GT(suns, 10);
  EXPECT_GT(glossy, 10);
  EXPECT_GT(metals, 10);
  EXPECT_GT(mirrors, 3);
  EXPECT_GT(patterns, 10);
  EXPECT_GT(moving, 10);
}

TEST(Procedural, LoadsByName) {
  EXPECT_EQ(Scene::load("procedural:3:5")->frameCount(), 5);
  EXPECT_EQ(Scene::load("procedural:3")->name(), "procedural_3");
  EXPECT_THROW(Scene::load("procedural:x"), Error);
  EXPECT_THROW(Scene::load("procedural:3:0"), Error);
  EXPECT_THROW(sceneFromJson(R"({"objects": [{"shape": "box", "material": {"pattern": {"kind": "swirl"}}}]})"), Error);
}

// Checklist 33 (pixel-perfect data): an emissive disc tilted against a black sky. Without jitter
// (the data set's setting) the pixels the albedo buffer marks as hit are exactly the pixels the
// reference sees lit; with jitter the reference's edge pixels are fractional and the masks differ.
TEST(Dataset, FeaturesAndReferenceArePixelAligned) {
  const std::string text = R"({"objects": [{"shape": "sphere", "scale": 1.3, "translation": [0.1, 0, 0],
      "material": {"baseColor": 0.5, "emissive": 2, "specular": 0}}],
      "camera": {"position": [0, 0, 4], "target": [0, 0, 0], "fov": 40}})";
  for (bool jitter : {false, true}) {
    RenderSettings s = tiny(40, 30);
    s.pixelJitter = jitter;
    Renderer r(sceneFromJson(text), s);
    const Frame f = r.render(0);
    const Image ref = r.renderReference(0, 16);
    int edges = 0, mismatches = 0;
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x) {
        const bool hit = f[Buffer::Albedo].at(x, y, 0) > 0;
        const float lit = ref.at(x, y, 0);
        mismatches += hit != (lit > 0) || (hit && std::abs(lit - 2.0f) > 1e-4f);
        edges += hit && x > 0 && !(f[Buffer::Albedo].at(x - 1, y, 0) > 0);
      }
    ASSERT_GT(edges, 10);
    if (!jitter) { EXPECT_EQ(mismatches, 0); }
    else EXPECT_GT(mismatches, 10) << "jittered references blur the edges (the test can fail)";
  }
}

// The data set: two runs with one seed give byte-identical caches (on 1 and 2 threads), another
// seed another one; dataset.json records the split and the convergence; the cache holds what
// the sequence and its reference hold.
TEST(Dataset, DeterministicForASeed) {
  const fs::path dir = tempDir("dataset");
  const std::string common = "dataset --builtin cornell --test cornell --procedural 1 --test-every 0 --frames 2 --size 24x16 "
                             "--reference-spp 4 --max-reference-spp 8 --no-reference-cache";
  std::string out;
  ASSERT_EQ(runCli(common + " --seed 2 --threads 1 --output " + (dir / "a").string(), out), 0) << out;
  ASSERT_EQ(runCli(common + " --seed 2 --threads 2 --output " + (dir / "b").string(), out), 0) << out;
  ASSERT_EQ(runCli(common + " --seed 3 --threads 2 --output " + (dir / "c").string(), out), 0) << out;
  const std::string cacheA = readFile(dir / "a/train/procedural_2000/cache.npy");
  ASSERT_GT(cacheA.size(), size_t(2 * 18 * 24 * 16 * 2));
  EXPECT_EQ(cacheA, readFile(dir / "b/train/procedural_2000/cache.npy"));
  EXPECT_EQ(readFile(dir / "a/test/cornell/cache.npy"), readFile(dir / "b/test/cornell/cache.npy"));
  EXPECT_NE(readFile(dir / "a/test/cornell/cache.npy"), readFile(dir / "c/test/cornell/cache.npy"));
  EXPECT_EQ(readFile(dir / "a/train/procedural_2000/scene.json"), proceduralSceneJson(2000, {2, 24, 16}) + "\n");

  const json index = json::parse(readFile(dir / "a/dataset.json"));
  EXPECT_TRUE(index["complete"].get<bool>());
  ASSERT_EQ(index["sequences"].size(), 2u);
  EXPECT_EQ(index["sequences"][0]["split"], "train");
  EXPECT_EQ(index["sequences"][1]["split"], "test");
  for (const auto& f : index["sequences"][0]["frameInfo"]) {
    EXPECT_GE(f["referenceSpp"].get<int>(), 4);
    EXPECT_GE(f["rmseHalf"].get<double>(), 0.0);
  }

  // The cache: a .npy header, then float16 [2, 18, 16, 24]; its colour and reference channels
  // are the sequence's (read with the library's reader) rounded to float16.
  ASSERT_EQ(cacheA.compare(0, 6, "\x93NUMPY"), 0);
  const size_t headerLen = size_t(uint8_t(cacheA[8])) | size_t(uint8_t(cacheA[9])) << 8;
  EXPECT_NE(cacheA.find("'shape': (2, 18, 16, 24)"), std::string::npos);
  EXPECT_EQ((10 + headerLen) % 64, 0u);
  const auto seq = SequenceReader::open(dir / "a/train/procedural_2000");
  const auto ref = SequenceReader::open(dir / "a/train/procedural_2000/reference");
  const Frame f1 = seq->read(1), r1 = ref->read(1);
  auto half = [&](int frame, int channel, int x, int y) {
    uint16_t h;
    std::memcpy(&h, cacheA.data() + 10 + headerLen + 2 * (((size_t(frame) * 18 + channel) * 16 + y) * 24 + x), 2);
    return h;
  };
  auto toHalfBits = [](float v) {  // round to nearest float16 (values here are normal and < 2^15)
    uint32_t b;
    std::memcpy(&b, &v, 4);
    if (v == 0) return uint16_t(0);
    const int e = int((b >> 23) & 0xFF) - 127 + 15;
    uint32_t m = b & 0x7FFFFF;
    uint32_t r = (uint32_t(e) << 10) | (m >> 13);
    const uint32_t rest = m & 0x1FFF;
    if (rest > 0x1000 || (rest == 0x1000 && (r & 1))) ++r;
    return uint16_t(r);
  };
  for (int y : {0, 7, 15})
    for (int x : {0, 11, 23}) {
      const float c = f1[Buffer::Color].at(x, y, 1), rr = r1[Buffer::Color].at(x, y, 2);
      if (c >= 6.2e-5f) { EXPECT_EQ(half(1, 1, x, y), toHalfBits(c)) << x << "," << y; }
      if (rr >= 6.2e-5f) { EXPECT_EQ(half(1, 17, x, y), toHalfBits(rr)) << x << "," << y; }
    }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtd::render::test
