// Issue 21: inputs that made a fuzz target fail are kept in tests/fixtures/fuzz/<target>/
// (README.md there says what each is) and must now fail fast with an rtd::Error naming the
// file, read the way that target reads its input: fuzz_native_sequence's frame of a one-frame
// native sequence, fuzz_blender_sequence's frame of a directory without sequence.json,
// fuzz_per_buffer's format byte and file (fuzz::writeInput).
// scripts/fuzz.sh also starts each fuzz target from its fixtures, under ASan.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "../../fuzz/fuzz_util.h"  // the fuzz targets' set-up
#include "io/image_file.h"
#include "rtd/rtd.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> fixtures(const std::string& target) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(RTD_SOURCE_DIR) / "tests/fixtures/fuzz" / target))
    if (e.path().filename() != "README.md") out.push_back(e.path());
  return out;
}

std::vector<uint8_t> bytesOf(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Lays each fixture out as the target reads it (fuzz::writeInput) and requires an rtd::Error
// that names the file the reader was given (`inputName`).
void expectNamedError(const std::string& target, fuzz::Target kind, const std::string& inputName) {
  const auto files = fixtures(target);
  ASSERT_FALSE(files.empty()) << target;
  for (const fs::path& file : files) {
    const fs::path dir = fs::temp_directory_path() / ("rtd_fuzz_regression_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    if (kind == fuzz::Target::NativeSequence) fuzz::writeNativeManifest(dir);
    const std::vector<uint8_t> bytes = bytesOf(file);
    ASSERT_TRUE(fuzz::writeInput(kind, dir, bytes.data(), bytes.size())) << file;
    try {
      SequenceReader::open(dir)->read(0);
      ADD_FAILURE() << file << ": read without an error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(inputName), std::string::npos) << file << ": " << e.what();
    }
    fs::remove_all(dir);
  }
}

TEST(FuzzRegression, NativeSequenceFixturesFailWithANamedError) {
  expectNamedError("native_sequence", fuzz::Target::NativeSequence, "frame_0001.exr");
}
TEST(FuzzRegression, BlenderSequenceFixturesFailWithANamedError) {
  expectNamedError("blender_sequence", fuzz::Target::BlenderSequence, "frame_0001.exr");
}
TEST(FuzzRegression, PerBufferFixturesFailWithANamedError) {
  if (!rtd::io::otherFormatsAvailable()) GTEST_SKIP() << "no OpenImageIO module: PNG is not read";
  expectNamedError("per_buffer", fuzz::Target::PerBuffer, "color_0001.");
}

}  // namespace
}  // namespace rtd
