// `rtdenoise denoise` (mono and stereo) overlaps reading and writing with denoising (apps/rtdenoise/io_pipeline.h;
// --no-pipeline turns it off). The overlap must not change anything but the time: the same
// bytes in every output, history reset at the same cuts and gaps; a frame that cannot be read
// stops the run with the earlier frames written and none after it; an output that cannot be
// written fails the run cleanly (exit 1, the file named, no temporary file left).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

#include "rtd/rtd.h"
#include "synthetic/synthetic.h"
#include "support/files.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;

// Frames numbered 0, 1, 2, 4, 5, 6, ... (a gap before 4, which resets history) with a marked
// cut at the second-to-last one: the loop's cut handling runs in both modes.
std::vector<int> writeSequence(const fs::path& dir, int frames) {
  synthetic::Scene scene;
  scene.width = 24;
  scene.height = 16;
  SequenceWriter writer(dir);
  std::vector<int> numbers;
  for (int k = 0; k < frames; ++k) {
    Frame f = synthetic::makeFrame(scene, k);
    f.number = k < 3 ? k : k + 1;
    f.cut = k == frames - 2;
    writer.write(f);
    numbers.push_back(f.number);
  }
  writer.finish();
  return numbers;
}

std::string frameFile(int number) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.exr", number);
  return name;
}

std::string contents(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs `prefix RTD_CLI args` through sh; the exit status (-1 if it did not exit), stderr in `err`.
int runCli(const std::string& prefix, const std::string& args, std::string& err) {
  const fs::path log = fs::temp_directory_path() / ("rtd_pipeline_cli_" + std::to_string(::getpid()) + ".log");
  const int status = std::system((prefix + " " + RTD_CLI + " " + args + " > /dev/null 2> " + log.string()).c_str());
  err = contents(log);
  fs::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(DenoisePipeline, SameBytesWithAndWithoutThePipeline) {
  const fs::path dir = test::scratchDir("rtd_pipeline", "same");
  const std::vector<int> numbers = writeSequence(dir / "in", 7);
  // svgf carries history from frame to frame; --half and --preview take the other write paths.
  for (const std::string extra : {"", " --half --preview"}) {
    std::string err;
    const std::string args = "denoise -m svgf --overwrite -i " + (dir / "in").string() + extra;
    ASSERT_EQ(runCli("", args + " -o " + (dir / "on").string(), err), 0) << err;
    ASSERT_EQ(runCli("", args + " --no-pipeline -o " + (dir / "off").string(), err), 0) << err;
    EXPECT_EQ(entries(dir / "on"), entries(dir / "off"));
    for (int n : numbers) {
      const std::string exr = frameFile(n);
      ASSERT_TRUE(fs::exists(dir / "on" / exr)) << exr;
      EXPECT_EQ(contents(dir / "on" / exr), contents(dir / "off" / exr)) << exr << extra;
      if (!extra.empty()) {
        const std::string png = exr.substr(0, exr.size() - 4) + ".png";
        EXPECT_EQ(contents(dir / "on" / png), contents(dir / "off" / png)) << png;
      }
    }
  }
  fs::remove_all(dir);
}

// A stereo input (left/, right/): both eyes go through the same pipeline.
TEST(DenoisePipeline, StereoSameBytesWithAndWithoutThePipeline) {
  const fs::path dir = test::scratchDir("rtd_pipeline", "stereo");
  std::vector<int> numbers;
  for (const char* eye : {"left", "right"}) numbers = writeSequence(dir / "in" / eye, 4);
  std::string err;
  const std::string args = "denoise -m svgf -i " + (dir / "in").string();
  ASSERT_EQ(runCli("", args + " -o " + (dir / "on").string(), err), 0) << err;
  ASSERT_EQ(runCli("", args + " --no-pipeline -o " + (dir / "off").string(), err), 0) << err;
  for (const char* eye : {"left", "right"})
    for (int n : numbers) {
      const fs::path on = dir / "on" / eye / frameFile(n);
      ASSERT_TRUE(fs::exists(on)) << on;
      EXPECT_EQ(contents(on), contents(dir / "off" / eye / frameFile(n))) << on;
    }
  fs::remove_all(dir);
}

TEST(DenoisePipeline, AnUnreadableFrameStopsTheRunAfterTheEarlierFramesAreWritten) {
  const fs::path dir = test::scratchDir("rtd_pipeline", "unreadable");
  const std::vector<int> numbers = writeSequence(dir / "in", 6);
  const size_t bad = 3;  // frame number 4
  const fs::path victim = dir / "in" / frameFile(numbers[bad]);
  const std::string whole = contents(victim);
  std::ofstream(victim, std::ios::binary | std::ios::trunc) << whole.substr(0, whole.size() * 2 / 3);
  for (const std::string mode : {"", " --no-pipeline"}) {
    const fs::path out = dir / ("out" + std::to_string(mode.size()));
    std::string err;
    EXPECT_EQ(runCli("", "denoise -m svgf -i " + (dir / "in").string() + " -o " + out.string() + mode, err), 1) << err;
    EXPECT_NE(err.find("frame " + std::to_string(numbers[bad])), std::string::npos) << err;
    EXPECT_NE(err.find(victim.string()), std::string::npos) << err;
    std::vector<std::string> expected;
    for (size_t k = 0; k < bad; ++k) expected.push_back(frameFile(numbers[k]));
    EXPECT_EQ(entries(out), expected) << "mode '" << mode << "': the frames before the bad one, nothing after";
  }
  fs::remove_all(dir);
}

TEST(DenoisePipeline, AnOutputThatCannotBeWrittenFailsCleanly) {
  const fs::path dir = test::scratchDir("rtd_pipeline", "unwritable");
  writeSequence(dir / "in", 4);
  // A file-size limit of 512 bytes (SIGXFSZ ignored, so the writes fail with EFBIG, as on a
  // full disk): every frame's write fails, on the writer thread.
  const fs::path out = dir / "out";
  std::string err;
  EXPECT_EQ(runCli("trap '' XFSZ; ulimit -f 1;", "denoise -m svgf -i " + (dir / "in").string() + " -o " + out.string(), err), 1)
      << err;
  EXPECT_NE(err.find("cannot write '" + (out / frameFile(0)).string() + "'"), std::string::npos) << err;
  EXPECT_EQ(entries(out), std::vector<std::string>{}) << "no frame, no timings.json, no temporary file";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtd
