// Guide-ray samples in the native format (docs/sequence-format.md, "Guide-ray samples"): they
// round-trip bit-exactly, and inconsistent samples (count, buffers, offsets, values) are refused
// by the writer or the reader with an error naming the file, frame, channel or field; `rtdenoise
// denoise` exits 1 on them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>

#include "rtd/error.h"
#include "rtd/guide_rays.h"
#include "rtd/sequence.h"
#include "support/run_cli.h"
#include "support/files.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

constexpr int kGuideSamplesW = 6, kGuideSamplesH = 4;

Image randomImage(int channels, std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> u(lo, hi);
  Image img(kGuideSamplesW, kGuideSamplesH, channels);
  for (float& v : img.pixels) v = u(rng);
  return img;
}

/// A guide frame with color and the diffuse / specular split, and n samples with the same.
std::pair<Frame, GuideRaySamples> frameWithSamples(int number, int n, std::mt19937& rng) {
  Frame f;
  f.number = number;
  f.width = kGuideSamplesW;
  f.height = kGuideSamplesH;
  for (Buffer b : {Buffer::Color, Buffer::Diffuse, Buffer::Specular, Buffer::Albedo, Buffer::Normal})
    f[b] = randomImage(3, rng, 0.0f, 1.0f);
  f[Buffer::Depth] = randomImage(1, rng, 1.0f, 5.0f);
  GuideRaySamples s;
  for (int k = 0; k < n; ++k) {
    Frame sf;
    sf.number = number;
    sf.width = kGuideSamplesW;
    sf.height = kGuideSamplesH;
    for (Buffer b : {Buffer::Color, Buffer::Diffuse, Buffer::Specular, Buffer::Normal}) sf[b] = randomImage(3, rng, 0.0f, 1.0f);
    sf[Buffer::Depth] = randomImage(1, rng, 1.0f, 5.0f);
    s.samples.push_back(sf);
    s.offsets.push_back(randomImage(2, rng, -0.5f, 0.5f));
  }
  return {f, s};
}

void writeJson(const fs::path& p, const nlohmann::json& j) { std::ofstream(p) << j.dump(1); }

TEST(GuideRaySampleFiles, RoundTripBitExactlyWithTheirBuffersInSequenceJson) {
  const fs::path dir = test::scratchDir("rtd_guide_samples", "roundtrip");
  std::mt19937 rng(7);
  std::vector<std::pair<Frame, GuideRaySamples>> written;
  {
    SequenceWriter w(dir);
    for (int i = 1; i <= 2; ++i) {
      written.push_back(frameWithSamples(i, 3, rng));
      w.write(written.back().first, &written.back().second);
    }
    w.finish();
  }
  const auto j = rtd::test::readJson(dir / "sequence.json");
  EXPECT_EQ(j["guideRays"]["samples"], 3);
  auto reader = SequenceReader::open(dir);
  ASSERT_EQ(reader->guideRaySampleCount(), 3);
  EXPECT_EQ(reader->guideRaySampleBuffers(),
            (std::vector<Buffer>{Buffer::Color, Buffer::Normal, Buffer::Depth, Buffer::Diffuse, Buffer::Specular}));
  for (int i = 0; i < 2; ++i) {
    const Frame f = reader->read(i);
    EXPECT_EQ(f[Buffer::Color].pixels, written[size_t(i)].first[Buffer::Color].pixels);
    const GuideRaySamples s = reader->readGuideRaySamples(i);
    ASSERT_EQ(s.samples.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(s.offsets[k].pixels, written[size_t(i)].second.offsets[k].pixels);
      for (Buffer b : reader->guideRaySampleBuffers())
        EXPECT_EQ(s.samples[k][b].pixels, written[size_t(i)].second.samples[k][b].pixels) << bufferName(b);
      EXPECT_FALSE(s.samples[k].has(Buffer::Albedo));
    }
  }
  // A sequence without samples says so.
  const fs::path plain = test::scratchDir("rtd_guide_samples", "plain");
  {
    SequenceWriter w(plain);
    w.write(written[0].first);
    w.finish();
  }
  auto plainReader = SequenceReader::open(plain);
  EXPECT_EQ(plainReader->guideRaySampleCount(), 0);
  EXPECT_FALSE(rtd::test::readJson(plain / "sequence.json").contains("guideRays"));
  EXPECT_TRUE(has(test::errorOf([&] { plainReader->readGuideRaySamples(0); }), "no guide-ray samples"));
  fs::remove_all(dir);
  fs::remove_all(plain);
}

TEST(GuideRaySampleFiles, WriterRefusesInconsistentSamples) {
  const fs::path dir = test::scratchDir("rtd_guide_samples", "writer");
  std::mt19937 rng(8);
  SequenceWriter w(dir);
  // Named variables, not structured bindings: clang 14 (the asan build) cannot capture those.
  auto first = frameWithSamples(1, 2, rng);
  const Frame& f1 = first.first;
  GuideRaySamples& s1 = first.second;
  // A radiance buffer of the frame missing in the samples: the mixed colour would not be the
  // sum of the lobes.
  GuideRaySamples noLobe = s1;
  for (Frame& sf : noLobe.samples) sf[Buffer::Specular] = Image();
  EXPECT_TRUE(has(test::errorOf([&] { w.write(f1, &noLobe); }), "'specular'"));
  GuideRaySamples noDepth = s1;
  for (Frame& sf : noDepth.samples) sf[Buffer::Depth] = Image();
  EXPECT_TRUE(has(test::errorOf([&] { w.write(f1, &noDepth); }), "'depth'"));
  GuideRaySamples fewOffsets = s1;
  fewOffsets.offsets.pop_back();
  EXPECT_TRUE(has(test::errorOf([&] { w.write(f1, &fewOffsets); }), "offset images"));
  w.write(f1, &s1);
  auto second = frameWithSamples(2, 3, rng);
  const Frame& f2 = second.first;
  GuideRaySamples& s2 = second.second;
  const std::string msg = test::errorOf([&] { w.write(f2, &s2); });
  EXPECT_TRUE(has(msg, "frame 2") && has(msg, "differ from the first frame")) << msg;
  EXPECT_TRUE(has(test::errorOf([&] { w.write(f2); }), "frame 2"));
  fs::remove_all(dir);
}

TEST(GuideRaySampleFiles, ReaderNamesTheFileFrameAndChannelOfBadSamples) {
  std::mt19937 rng(9);
  auto make = [&](const std::string& name, const std::function<void(GuideRaySamples&)>& spoil) {
    const fs::path dir = test::scratchDir("rtd_guide_samples", name);
    SequenceWriter w(dir);
    for (int i = 1; i <= 2; ++i) {
      auto [f, s] = frameWithSamples(i, 2, rng);
      if (i == 2) spoil(s);
      w.write(f, &s);
    }
    w.finish();
    return dir;
  };
  // An offset outside the pixel, a non-finite and a negative radiance in frame 2.
  const fs::path offset = make("offset", [](GuideRaySamples& s) { s.offsets[1].at(4, 2, 0) = 0.75f; });
  const fs::path nan = make("nan", [](GuideRaySamples& s) { s.samples[0][Buffer::Diffuse].at(1, 3, 2) = NAN; });
  const fs::path negative = make("negative", [](GuideRaySamples& s) { s.samples[1][Buffer::Color].at(0, 0, 0) = -1.0f; });
  struct Case {
    fs::path dir;
    const char* channel;
    const char* pixel;
    const char* what;
  };
  for (const Case& c : {Case{offset, "sample2.offset.X", "(4, 2)", "outside [-0.5, 0.5]"},
                        Case{nan, "sample1.diffuse.B", "(1, 3)", "not finite"},
                        Case{negative, "sample2.color.R", "(0, 0)", "negative"}}) {
    auto reader = SequenceReader::open(c.dir);
    EXPECT_NO_THROW(reader->readGuideRaySamples(0));
    const std::string msg = test::errorOf([&] { reader->readGuideRaySamples(1); });
    for (const std::string& part : {std::string("frame 2"), std::string("frame_0002.exr"), std::string(c.channel),
                                   std::string(c.pixel), std::string(c.what)})
      EXPECT_TRUE(has(msg, part)) << part << " not in: " << msg;
    // The CLI stops with exit status 1 and the same message, after frame 1.
    const auto r = test::runCli("denoise -m accumulate -i " + c.dir.string() + " -o " + (c.dir / "out").string());
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_TRUE(has(r.output, c.channel)) << r.output;
    EXPECT_TRUE(fs::exists(c.dir / "out" / "frame_0001.exr"));
    EXPECT_FALSE(fs::exists(c.dir / "out" / "frame_0002.exr"));
    fs::remove_all(c.dir);
  }

  // sequence.json claiming more samples than the files hold: the missing channel is named.
  const fs::path more = make("more", [](GuideRaySamples&) {});
  nlohmann::json j = rtd::test::readJson(more / "sequence.json");
  j["guideRays"]["samples"] = 3;
  writeJson(more / "sequence.json", j);
  const std::string msg = test::errorOf([&] { SequenceReader::open(more)->readGuideRaySamples(0); });
  EXPECT_TRUE(has(msg, "frame 1") && has(msg, "frame_0001.exr") && has(msg, "sample3.")) << msg;

  // Bad 'guideRays' fields are refused when the sequence is opened, naming the field.
  const nlohmann::json original = rtd::test::readJson(more / "sequence.json");
  auto refused = [&](const std::function<void(nlohmann::json&)>& edit, const std::string& part) {
    nlohmann::json e = original;
    edit(e);
    writeJson(more / "sequence.json", e);
    const std::string m = test::errorOf([&] { SequenceReader::open(more); });
    EXPECT_TRUE(has(m, "sequence.json") && has(m, part)) << part << " not in: " << m;
  };
  refused([](nlohmann::json& e) { e["guideRays"]["samples"] = 0; }, "'guideRays.samples'");
  refused([](nlohmann::json& e) { e["guideRays"]["samples"] = 1000; }, "'guideRays.samples'");
  refused([](nlohmann::json& e) { e["guideRays"]["buffers"] = {"color", "depth", "normal", "diffuse"}; },
          "radiance buffer 'specular'");
  refused([](nlohmann::json& e) { e["guideRays"]["buffers"] = {"color", "depth", "diffuse", "specular"}; }, "'normal'");
  refused([](nlohmann::json& e) { e["guideRays"]["buffers"] = {"color", "depth", "normal", "diffuse", "specular", "albedo"}; },
          "'albedo'");
  refused([](nlohmann::json& e) { e["guideRays"]["buffers"] = {"color", "color"}; }, "listed twice");
  refused([](nlohmann::json& e) { e["guideRays"] = 3; }, "'guideRays'");
  fs::remove_all(more);
}

}  // namespace
}  // namespace rtd
