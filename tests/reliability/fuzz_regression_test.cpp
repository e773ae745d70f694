// Issue 21: inputs that made a fuzz target fail are kept in tests/fixtures/fuzz/<target>/
// (README.md there says what each is) and must now fail fast with an rtd::Error naming the
// file, read the way that target reads its input: fuzz_native_sequence's frame of a one-frame
// native sequence, fuzz_blender_sequence's frame of a directory without sequence.json.
// scripts/fuzz.sh also starts each fuzz target from its fixtures, under ASan.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "../../fuzz/fuzz_util.h"  // the fuzz targets' set-up
#include "rtd/rtd.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> fixtures(const std::string& target) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(RTD_SOURCE_DIR) / "tests/fixtures/fuzz" / target))
    if (e.path().extension() == ".exr") out.push_back(e.path());
  return out;
}

void expectNamedError(const std::string& target, bool native) {
  const auto files = fixtures(target);
  ASSERT_FALSE(files.empty()) << target;
  for (const fs::path& file : files) {
    const fs::path dir = fs::temp_directory_path() / ("rtd_fuzz_regression_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    if (native) fuzz::writeNativeManifest(dir);
    fs::copy_file(file, dir / "frame_0001.exr");
    try {
      SequenceReader::open(dir)->read(0);
      ADD_FAILURE() << file << ": read without an error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("frame_0001.exr"), std::string::npos) << file << ": " << e.what();
    }
    fs::remove_all(dir);
  }
}

TEST(FuzzRegression, NativeSequenceFixturesFailWithANamedError) { expectNamedError("native_sequence", true); }
TEST(FuzzRegression, BlenderSequenceFixturesFailWithANamedError) { expectNamedError("blender_sequence", false); }

}  // namespace
}  // namespace rtd
