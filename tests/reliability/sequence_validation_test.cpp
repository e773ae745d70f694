// Issue 21: sequences are validated on the way in. Duplicate frame numbers used to overwrite an
// output frame silently, 2^31 wrapped to a negative number, a gap in the numbering was treated
// as consecutive frames, a camera cut could not be expressed, a list-form cameras.json was keyed
// by list index, and bad sizes or indices surfaced as std::out_of_range, "stoi" or "cannot create
// std::vector larger than max_size()". Each case, through the library and the CLI.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "rtd/rtd.h"
#include "support/test_frames.h"
#include "synthetic/synthetic.h"
#include "support/files.h"
#include "support/run_cli.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A native sequence of synthetic frames numbered `numbers`.
void writeSequence(const fs::path& dir, const std::vector<int>& numbers, int w = 24, int h = 16) {
  synthetic::Scene scene;
  scene.width = w;
  scene.height = h;
  SequenceWriter writer(dir);
  for (size_t k = 0; k < numbers.size(); ++k) {
    Frame f = synthetic::makeFrame(scene, int(k));
    f.number = numbers[k];
    writer.write(f);
  }
  writer.finish();
}

json readManifest(const fs::path& dir) {
  std::ifstream in(dir / "sequence.json");
  return json::parse(in);
}
void writeManifest(const fs::path& dir, const json& j) { std::ofstream(dir / "sequence.json") << j.dump(1); }

TEST(SequenceValidation, DuplicateFrameNumbersAreRefused) {
  const fs::path dir = test::scratchDir("rtd_seqval", "dup");
  writeSequence(dir, {1, 2, 3, 4});
  json j = readManifest(dir);
  j["frames"][2]["number"] = 2;  // two frames 2: the second would overwrite the first's output
  writeManifest(dir, j);
  const std::string msg = test::errorOf([&] { SequenceReader::open(dir); });
  EXPECT_NE(msg.find("frame 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("twice"), std::string::npos) << msg;
  auto [code, err] = test::runCliStderr("denoise -m accumulate -i " + dir.string() + " -o " + (dir / "out").string());
  EXPECT_EQ(code, 1) << err;
  EXPECT_FALSE(fs::exists(dir / "out" / "frame_0002.exr"));
  // The writer refuses a number written twice as well.
  SequenceWriter writer(dir / "w");
  Frame f = test::flatFrame(4, 4, 1.0f);
  f.number = 7;
  writer.write(f);
  EXPECT_NE(test::errorOf([&] { writer.write(f); }).find("already written"), std::string::npos);
  fs::remove_all(dir);
}

TEST(SequenceValidation, FrameNumbersOutOfRangeAreRefused) {
  const fs::path dir = test::scratchDir("rtd_seqval", "range");
  writeSequence(dir, {1, 2});
  for (const json& bad : {json(2147483648LL), json(-1), json(1.5), json("3")}) {
    json j = readManifest(dir);
    j["frames"][1]["number"] = bad;
    writeManifest(dir, j);
    const std::string msg = test::errorOf([&] { SequenceReader::open(dir); });
    EXPECT_NE(msg.find("sequence.json"), std::string::npos) << bad << ": " << msg;
    EXPECT_NE(msg.find("frame number " + bad.dump()), std::string::npos) << bad << ": " << msg;
  }
  fs::remove_all(dir);
}

TEST(SequenceValidation, ImageSizesAreCheckedBeforeAnythingIsAllocated) {
  const fs::path dir = test::scratchDir("rtd_seqval", "size");
  writeSequence(dir, {1, 2});
  for (const auto& [w, h] : std::vector<std::pair<long long, long long>>{{-24, 16}, {0, 16}, {24, 1000000}, {200000, 200000}}) {
    json j = readManifest(dir);
    j["width"] = w;
    j["height"] = h;
    writeManifest(dir, j);
    const std::string msg = test::errorOf([&] { SequenceReader::open(dir); });
    EXPECT_NE(msg.find("sequence.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find(std::to_string(w) + "x" + std::to_string(h)), std::string::npos) << msg;
  }
  fs::remove_all(dir);
}

TEST(SequenceValidation, OutOfRangeIndicesAreRtdErrors) {
  const fs::path dir = test::scratchDir("rtd_seqval", "index");
  writeSequence(dir, {1, 2});
  auto seq = SequenceReader::open(dir);
  for (int i : {-1, 2, 1000}) {
    EXPECT_NE(test::errorOf([&] { seq->read(i); }).find("out of range"), std::string::npos) << i;
    EXPECT_NE(test::errorOf([&] { seq->framePath(i); }).find("out of range"), std::string::npos) << i;
    EXPECT_NE(test::errorOf([&] { seq->frameNumber(i); }).find("out of range"), std::string::npos) << i;
  }
  fs::remove_all(dir);
}

TEST(SequenceValidation, HugeFrameNumbersInFileNamesNameTheFile) {
  const fs::path dir = test::scratchDir("rtd_seqval", "bigname");
  fs::copy_file(fs::path(RTD_SOURCE_DIR) / "tests/fixtures/blender/frame_0001.exr", dir / "frame_99999999999.exr");
  const std::string msg = test::errorOf([&] { SequenceReader::open(dir); });
  EXPECT_NE(msg.find("frame_99999999999.exr"), std::string::npos) << msg;
  EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
  fs::remove_all(dir);
}

// A gap (1, 2, 5, 6) resets history at 5 unless the sequence or the caller declares the
// numbering continuous; `cut` marks a cut explicitly. A frame at which history is reset gives
// exactly what a fresh denoiser gives for it.
TEST(SequenceValidation, GapsAndMarkedCutsResetHistory) {
  const fs::path dir = test::scratchDir("rtd_seqval", "gaps");
  writeSequence(dir, {1, 2, 5, 6, 7});
  auto cuts = [](const SequenceReader& r) {
    std::vector<int> out;
    for (int i = 0; i < r.frameCount(); ++i)
      if (r.read(i).cut) out.push_back(r.frameNumber(i));
    return out;
  };
  EXPECT_EQ(cuts(*SequenceReader::open(dir)), std::vector<int>{5});
  EXPECT_EQ(cuts(*SequenceReader::open(dir, {.continuous = true})), std::vector<int>{});
  EXPECT_EQ(cuts(*SequenceReader::open(dir, {.cuts = {7}, .continuous = true})), std::vector<int>{7});
  json j = readManifest(dir);
  j["continuous"] = true;
  j["frames"][3]["cut"] = true;  // frame 6
  writeManifest(dir, j);
  auto seq = SequenceReader::open(dir);
  EXPECT_EQ(cuts(*seq), std::vector<int>{6});

  // The denoiser resets at the cut: frame 6's output equals a fresh denoiser's.
  auto device = Device::create({.threads = 1});
  auto d = device->createDenoiser("svgf"), fresh = device->createDenoiser("svgf");
  Image out(seq->width(), seq->height(), 3), ref(seq->width(), seq->height(), 3);
  for (int i = 0; i < 4; ++i) d->denoise(seq->read(i).inputs(), out.view());
  fresh->denoise(seq->read(3).inputs(), ref.view());
  EXPECT_EQ(out.pixels, ref.pixels);
  // Without the cut (the frame's inputs with cameraCut cleared) history is used.
  auto noCut = device->createDenoiser("svgf");
  for (int i = 0; i < 4; ++i) {
    const Frame frame = seq->read(i);  // the views of `in` point into it
    FrameInputs in = frame.inputs();
    in.cameraCut = false;
    noCut->denoise(in, out.view());
  }
  EXPECT_NE(out.pixels, ref.pixels);
  fs::remove_all(dir);
}

// A cameras.json as a list of {"frame": N, ...} entries is keyed by "frame" (it was keyed by
// list index, giving frame N frame N+1's camera); entries without one, and keys that are not
// frame numbers, are refused.
TEST(SequenceValidation, BlenderCameraListIsKeyedByFrame) {
  const fs::path fixture = fs::path(RTD_SOURCE_DIR) / "tests/fixtures/blender";
  const fs::path dir = test::scratchDir("rtd_seqval", "cameras");
  for (int n = 1; n <= 3; ++n) {
    const std::string name = "frame_000" + std::to_string(n) + ".exr";
    fs::copy_file(fixture / name, dir / name);
  }
  json cams;
  {
    std::ifstream in(fixture / "cameras.json");
    cams = json::parse(in);
  }
  // Frames 3, 1, 2 (out of order), each entry with its frame number.
  json list = json::array();
  for (int n : {3, 1, 2}) {
    json e = cams["cameras"][std::to_string(n)];
    e["frame"] = n;
    list.push_back(e);
  }
  for (const json& file : {json{{"cameras", list}}, list}) {
    std::ofstream(dir / "cameras.json") << file.dump();
    auto seq = SequenceReader::open(dir);
    for (int i = 0; i < 3; ++i) {
      const Frame f = seq->read(i);
      ASSERT_TRUE(f.camera.valid);
      const auto& row0 = cams["cameras"][std::to_string(f.number)]["world_to_camera"][0];
      for (int k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(f.camera.worldToCamera[size_t(k)], row0[size_t(k)].get<float>()) << f.number;
    }
  }
  list[1].erase("frame");
  std::ofstream(dir / "cameras.json") << json{{"cameras", list}}.dump();
  EXPECT_NE(test::errorOf([&] { SequenceReader::open(dir); }).find("'frame'"), std::string::npos);
  std::ofstream(dir / "cameras.json") << json{{"cameras", {{"one", cams["cameras"]["1"]}}}}.dump();
  EXPECT_NE(test::errorOf([&] { SequenceReader::open(dir); }).find("camera key 'one'"), std::string::npos);
  fs::remove_all(dir);
}

// The CLI marks cuts for any input (here the Blender fixture): timings.json records them and
// the cut frame is denoised from fresh history.
TEST(SequenceValidation, CliCutOptionResetsHistory) {
  const fs::path fixture = fs::path(RTD_SOURCE_DIR) / "tests/fixtures/blender";
  const fs::path out = test::scratchDir("rtd_seqval", "cli_cut");
  auto [code, err] = test::runCliStderr("denoise -m accumulate --threads 1 --cut 3 -i " + fixture.string() + " -o " + out.string());
  ASSERT_EQ(code, 0) << err;
  std::ifstream in(out / "timings.json");
  const json t = json::parse(in);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(t["frames"][size_t(i)].value("cut", false), i == 2) << i;
  auto seq = SequenceReader::open(fixture);
  auto fresh = Device::create({.threads = 1})->createDenoiser("accumulate");
  Image ref(seq->width(), seq->height(), 3);
  fresh->denoise(seq->read(2).inputs(), ref.view());
  const Image got = readRgbExr(out / "frame_0003.exr");
  for (size_t k = 0; k < ref.pixels.size(); ++k) ASSERT_EQ(got.pixels[k], ref.pixels[k]) << k;
  fs::remove_all(out);
}

}  // namespace
}  // namespace rtd
