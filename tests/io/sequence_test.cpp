// Native sequence round trip, and every bad-input case of the foundation issue: sanitized
// radiance, a missing channel, frames of different sizes, a truncated file — each stops with
// an error naming the file and channel, exits non-zero, and leaves no truncated output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "io/exr.h"
#include "support/test_frames.h"
#include "synthetic/synthetic.h"
#include "support/files.h"
#include "support/run_cli.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;

/// Runs the CLI; returns its exit status and what it printed on stderr.
TEST(NativeSequence, RoundTripsEveryBufferAndTheCameras) {
  const fs::path dir = test::scratchDir("rtd_test", "roundtrip");
  synthetic::Scene scene;
  scene.width = 20;
  scene.height = 12;
  test::writeSyntheticSequence(dir, 3, scene.width, scene.height);
  auto seq = SequenceReader::open(dir);
  EXPECT_EQ(seq->kind(), SequenceKind::Native);
  ASSERT_EQ(seq->frameCount(), 3);
  for (int k = 0; k < 3; ++k) {
    const Frame expected = synthetic::makeFrame(scene, k), got = seq->read(k);
    EXPECT_EQ(got.number, k + 1);
    for (int b = 0; b < kBufferCount; ++b) {
      ASSERT_EQ(expected.has(Buffer(b)), got.has(Buffer(b))) << bufferName(Buffer(b));
      if (expected.has(Buffer(b))) { EXPECT_EQ(expected.buffers[b].pixels, got.buffers[b].pixels) << bufferName(Buffer(b)); }
    }
    EXPECT_TRUE(got.camera.valid);
    EXPECT_EQ(got.camera.worldToCamera, expected.camera.worldToCamera);
    EXPECT_EQ(got.camera.projection, expected.camera.projection);
  }
  fs::remove_all(dir);
}

TEST(BadInput, NonFiniteAndNegativeRadianceIsSanitizedAndCountedAndNeverReachesHistory) {
  Frame f = test::flatFrame(6, 4, 0.5f);
  f[Buffer::Color].at(1, 1, 0) = NAN;
  f[Buffer::Color].at(2, 1, 1) = INFINITY;
  f[Buffer::Color].at(3, 1, 2) = -2.0f;
  auto denoiser = Device::create()->createDenoiser("accumulate");
  Image out(6, 4, 3);
  denoiser->denoise(f.inputs(), out.view());
  EXPECT_EQ(denoiser->stats().sanitizedValues, 3u);
  EXPECT_TRUE(test::allFinite(out));
  EXPECT_EQ(out.at(1, 1, 0), 0.0f);
  // Clean frames afterwards: history is finite and converges back.
  const Frame clean = test::flatFrame(6, 4, 0.5f);
  for (int k = 0; k < 30; ++k) denoiser->denoise(clean.inputs(), out.view());
  EXPECT_EQ(denoiser->stats().sanitizedValues, 0u);
  EXPECT_TRUE(test::allFinite(out));
  EXPECT_NEAR(out.at(1, 1, 0), 0.5f, 1e-3);
}

TEST(BadInput, MissingRequiredBufferOrMismatchedSizesThrowBeforeTouchingHistory) {
  auto denoiser = Device::create()->createDenoiser("accumulate");
  Image out(6, 4, 3);
  FrameInputs empty;
  EXPECT_NE(test::errorOf([&] { denoiser->denoise(empty, out.view()); }).find("color"), std::string::npos);
  Frame f = test::flatFrame(6, 4, 0.5f);
  f[Buffer::Normal] = Image(5, 4, 3);
  EXPECT_NE(test::errorOf([&] { denoiser->denoise(f.inputs(), out.view()); }).find("'normal' is 5x4"), std::string::npos);
  Image small(3, 3, 3);
  EXPECT_NE(test::errorOf([&] { denoiser->denoise(test::flatFrame(6, 4, 0.5f).inputs(), small.view()); }), "");
}

TEST(BadInput, SettingsAreCheckedByNameTypeAndRange) {
  auto d = Device::create()->createDenoiser("accumulate");
  EXPECT_NE(test::errorOf([&] { d->set("nope", "1"); }).find("no setting 'nope'"), std::string::npos);
  EXPECT_NE(test::errorOf([&] { d->set("alpha", "abc"); }).find("'alpha'"), std::string::npos);
  EXPECT_NE(test::errorOf([&] { d->set("alpha", "2"); }).find("outside"), std::string::npos);
  EXPECT_NE(test::errorOf([&] { d->set("demodulate", "maybe"); }), "");
  d->set("alpha", "0.1");
  EXPECT_FLOAT_EQ(d->getSettings<AccumulateSettings>().alpha, 0.1f);
  EXPECT_NE(test::errorOf([&] { Device::create()->createDenoiser("unknown"); }).find("unknown method"), std::string::npos);
}

TEST(BadInput, MissingChannelNamesFileFrameAndChannel) {
  const fs::path dir = test::scratchDir("rtd_test", "missing");
  test::writeSyntheticSequence(dir, 3);
  // Rewrite frame 2 without normal.Y.
  const fs::path victim = dir / "frame_0002.exr";
  exr::Header h = exr::readHeader(victim);
  std::vector<std::string> keep;
  for (const auto& c : h.channels)
    if (c != "normal.Y") keep.push_back(c);
  auto planes = exr::readChannels(victim, keep, "");
  std::vector<exr::ChannelSource> src;
  for (size_t i = 0; i < keep.size(); ++i) src.push_back({keep[i], planes[i].data(), 1});
  exr::writeChannels(victim, h.width, h.height, src);

  auto seq = SequenceReader::open(dir);
  const std::string msg = test::errorOf([&] { seq->read(1); });
  EXPECT_NE(msg.find("frame 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("frame_0002.exr"), std::string::npos) << msg;
  EXPECT_NE(msg.find("normal.Y"), std::string::npos) << msg;

  const fs::path out = dir / "out";
  auto [code, err] = test::runCliStderr("denoise -m accumulate -i " + dir.string() + " -o " + out.string());
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("normal.Y"), std::string::npos) << err;
  // Frame 1 was written completely; frame 2 was never started; no temporary files remain.
  EXPECT_NO_THROW(readRgbExr(out / "frame_0001.exr"));
  EXPECT_FALSE(fs::exists(out / "frame_0002.exr"));
  for (const auto& e : fs::directory_iterator(out)) EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos);
  fs::remove_all(dir);
}

TEST(BadInput, FramesOfDifferentSizesAreRejectedNamingTheFile) {
  const fs::path dir = test::scratchDir("rtd_test", "sizes");
  test::writeSyntheticSequence(dir, 2);
  // Replace frame 2 by a frame of another size.
  const fs::path other = test::scratchDir("rtd_test", "sizes_other");
  test::writeSyntheticSequence(other, 2, 30, 10);
  fs::copy_file(other / "frame_0002.exr", dir / "frame_0002.exr", fs::copy_options::overwrite_existing);
  auto seq = SequenceReader::open(dir);
  const std::string msg = test::errorOf([&] { seq->read(1); });
  EXPECT_NE(msg.find("frame_0002.exr"), std::string::npos) << msg;
  EXPECT_NE(msg.find("30x10"), std::string::npos) << msg;
  auto [code, err] = test::runCliStderr("denoise -m accumulate -i " + dir.string() + " -o " + (dir / "out").string());
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("frame_0002.exr"), std::string::npos) << err;
  fs::remove_all(dir);
  fs::remove_all(other);
}

TEST(BadInput, TruncatedFileIsReportedNotHalfRead) {
  const fs::path dir = test::scratchDir("rtd_test", "truncated");
  test::writeSyntheticSequence(dir, 2);
  const fs::path victim = dir / "frame_0002.exr";
  const auto size = fs::file_size(victim);
  fs::resize_file(victim, size / 2);
  auto seq = SequenceReader::open(dir);
  const std::string msg = test::errorOf([&] { seq->read(1); });
  EXPECT_NE(msg.find("frame_0002.exr"), std::string::npos) << msg;
  EXPECT_NE(msg.find("frame 2"), std::string::npos) << msg;
  auto [code, err] = test::runCliStderr("denoise -m accumulate -i " + dir.string() + " -o " + (dir / "out").string());
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("frame_0002.exr"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "out" / "frame_0002.exr"));
  // A corrupt first file (garbage bytes) is reported too.
  std::ofstream(dir / "frame_0001.exr", std::ios::binary) << "not an exr";
  EXPECT_NE(test::errorOf([&] { SequenceReader::open(dir)->read(0); }).find("frame_0001.exr"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Cli, DenoisesTheBlenderFixtureWithTheSameNumberingAndTimings) {
  const fs::path out = test::scratchDir("rtd_test", "cli_blender");
  auto [code, err] = test::runCliStderr("denoise -m accumulate -i " + std::string(RTD_SOURCE_DIR) + "/tests/fixtures/blender -o " +
                            out.string());
  ASSERT_EQ(code, 0) << err;
  for (int n = 1; n <= 5; ++n) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", n);
    const Image img = readRgbExr(out / name);
    EXPECT_EQ(img.width, 64);
    EXPECT_TRUE(test::allFinite(img));
  }
  std::ifstream in(out / "timings.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["frames"].size(), 5u);
  EXPECT_TRUE(j["frames"][0]["passes"].contains("accumulate"));
  auto [badCode, badErr] = test::runCliStderr("denoise -m accumulate -i " + out.string() + "/nonexistent -o " + out.string());
  EXPECT_NE(badCode, 0);
  EXPECT_NE(badErr.find("nonexistent"), std::string::npos);
  fs::remove_all(out);
}

}  // namespace
}  // namespace rtd
