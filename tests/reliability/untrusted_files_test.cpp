// Issue 21: EXR files are untrusted. A header is checked against limits and the file's size
// before OpenEXR parses it: an attribute claiming 840 MB made OpenEXR allocate that much, a 2 MB
// file whose header claims 12000x12000 took 3.9 GB before failing. Each crafted file below must
// fail fast with an rtd::Error naming the file and what is wrong, through the native and the
// Blender readers and readRgbExr.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <functional>

#include "io/exr_limits.h"
#include "rtd/rtd.h"
#include "support/files.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;

std::vector<char> fileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void writeBytes(const fs::path& p, const std::vector<char>& b) {
  std::ofstream(p, std::ios::binary).write(b.data(), std::streamsize(b.size()));
}

// Offset of the value of header attribute `name` (after name, type and size).
size_t attributeValue(const std::vector<char>& b, const std::string& name, const std::string& type) {
  std::string key = name;
  key += '\0';
  key += type;
  key += '\0';
  const auto it = std::search(b.begin(), b.end(), key.begin(), key.end());
  EXPECT_NE(it, b.end()) << name;
  return size_t(it - b.begin()) + key.size() + 4;
}
void putInt(std::vector<char>& b, size_t at, int32_t v) { std::memcpy(&b[at], &v, 4); }

// Inserts a header attribute right after the magic number and version (the offset table is
// not moved: the files below must fail in their header).
void insertAttribute(std::vector<char>& b, const std::string& name, const std::string& type, const std::vector<int32_t>& ints) {
  std::vector<char> a(name.begin(), name.end());
  a.push_back('\0');
  a.insert(a.end(), type.begin(), type.end());
  a.push_back('\0');
  const int32_t size = int32_t(4 * ints.size());
  a.resize(a.size() + 4 + size_t(size));
  std::memcpy(&a[a.size() - 4 - size_t(size)], &size, 4);
  if (size > 0) std::memcpy(&a[a.size() - size_t(size)], ints.data(), size_t(size));
  b.insert(b.begin() + 8, a.begin(), a.end());
}

// A valid RGB EXR of 64x36 to mutate.
std::vector<char> validExr(const fs::path& dir) {
  Image img(64, 36, 3, 0.25f);
  writeRgbExr(dir / "valid.exr", img);
  return fileBytes(dir / "valid.exr");
}

struct Crafted {
  const char* what;
  const char* expect;
  std::function<void(std::vector<char>&)> edit;
};

std::vector<Crafted> craftedFiles() {
  return {
      {"an attribute claiming 840 MB", "header attribute 'pixelAspectRatio' claims 840000000 bytes",
       [](std::vector<char>& b) { putInt(b, attributeValue(b, "pixelAspectRatio", "float") - 4, 840000000); }},
      {"a negative attribute size", "cannot be negative",
       [](std::vector<char>& b) { putInt(b, attributeValue(b, "screenWindowWidth", "float") - 4, -5); }},
      {"a 12000x12000 data window", "12000x12000, larger than the largest image",
       [](std::vector<char>& b) {
         const size_t at = attributeValue(b, "dataWindow", "box2i");
         putInt(b, at + 8, 11999);
         putInt(b, at + 12, 11999);
       }},
      {"an 8000x8000 data window in a small file", "more than its",
       [](std::vector<char>& b) {
         // Within the size limits, but the few kilobytes of pixel data cannot hold it. The file
         // grows to hold the offset table of 500 ZIP chunks, which alone would pass.
         const size_t at = attributeValue(b, "dataWindow", "box2i");
         putInt(b, at + 8, 7999);
         putInt(b, at + 12, 7999);
         b.resize(b.size() + 500 * 16, 0);
       }},
      {"an empty data window", "empty size",
       [](std::vector<char>& b) { putInt(b, attributeValue(b, "dataWindow", "box2i") + 8, -10); }},
      {"a truncated offset table", "truncated",
       [](std::vector<char>& b) {
         const size_t at = attributeValue(b, "dataWindow", "box2i");
         putInt(b, at + 12, 35 + 16 * 100);  // 1636 rows: 103 chunks, no room for their table
       }},
      {"an unknown compression", "unknown compression",
       [](std::vector<char>& b) { b[attributeValue(b, "compression", "compression")] = 42; }},
      {"a subsampled channel", "subsampled",
       [](std::vector<char>& b) {
         const size_t at = attributeValue(b, "channels", "chlist");
         putInt(b, at + 2 + 8, 2);  // channel "B": name, type, pLinear+reserved, xSampling
       }},
      {"an unterminated attribute name", "longer than 31 characters",
       [](std::vector<char>& b) {
         for (size_t i = 8; i < 60; ++i) b[i] = 'x';
       }},
      {"a file cut inside its header", "the file ends inside",
       [](std::vector<char>& b) { b.resize(attributeValue(b, "dataWindow", "box2i") - 7); }},  // inside "box2i"
      // OpenEXR reads a known type by its own layout, not by the claimed size: a box2i claiming
      // 20 bytes would be read as 16 and the next attribute taken from inside it (a fuzz finding,
      // tests/fixtures/fuzz/blender_sequence).
      {"a box2i claiming 20 bytes", "'displayWindow' of type box2i claims 20 bytes; that type has 16",
       [](std::vector<char>& b) { putInt(b, attributeValue(b, "displayWindow", "box2i") - 4, 20); }},
      {"a float claiming 8 bytes", "of type float claims 8 bytes",
       [](std::vector<char>& b) { insertAttribute(b, "exposure", "float", {0, 0}); }},
      {"a channel list claiming more bytes than it has", "the channel list ends at byte",
       [](std::vector<char>& b) {  // 4 more bytes claimed, taken from the next attribute's name
         const size_t at = attributeValue(b, "channels", "chlist");
         int32_t size;
         std::memcpy(&size, &b[at - 4], 4);
         putInt(b, at - 4, size + 4);
       }},
      // String vectors and previews are parsed by content: it must fill the claimed size.
      {"a string vector whose string claims 1 MB", "a string of the vector claims 1000000 bytes",
       [](std::vector<char>& b) { insertAttribute(b, "names", "stringvector", {1000000, 0x64636261}); }},
      {"a 1000x1000 preview in 12 bytes", "preview image does not fit",
       [](std::vector<char>& b) { insertAttribute(b, "preview", "preview", {1000, 1000, 0}); }},
      {"not an EXR", "not an EXR", [](std::vector<char>& b) { b[0] = 'P'; }},
      {"a zero-byte file", "too short", [](std::vector<char>& b) { b.clear(); }},
  };
}

TEST(UntrustedFiles, CraftedHeadersFailFastNamingFileAndProblem) {
  const fs::path dir = test::scratchDir("rtd_untrusted", "crafted");
  const std::vector<char> valid = validExr(dir);
  for (const Crafted& c : craftedFiles()) {
    std::vector<char> b = valid;
    c.edit(b);
    const fs::path file = dir / "crafted.exr";
    writeBytes(file, b);
    for (const auto& [reader, call] : std::vector<std::pair<const char*, std::function<void()>>>{
             {"readRgbExr", [&] { readRgbExr(file); }},
             {"checkHeader", [&] { exr::checkHeader(file); }}}) {
      const std::string msg = test::errorOf(call);
      EXPECT_NE(msg.find("crafted.exr"), std::string::npos) << c.what << ", " << reader << ": " << msg;
      EXPECT_NE(msg.find(c.expect), std::string::npos) << c.what << ", " << reader << ": " << msg;
    }
  }
  // The unmodified file passes.
  writeBytes(dir / "crafted.exr", valid);
  EXPECT_EQ(readRgbExr(dir / "crafted.exr").width, 64);
  fs::remove_all(dir);
}

// The same through the sequence readers, named with the frame: a Blender frame with a huge
// attribute, and a native sequence whose second frame is crafted.
TEST(UntrustedFiles, SequenceReadersNameTheFrameAndFile) {
  const fs::path dir = test::scratchDir("rtd_untrusted", "blender");
  const fs::path fixture = fs::path(RTD_SOURCE_DIR) / "tests/fixtures/blender";
  for (int n = 1; n <= 2; ++n) fs::copy_file(fixture / ("frame_000" + std::to_string(n) + ".exr"), dir / ("frame_000" + std::to_string(n) + ".exr"));
  std::vector<char> b = fileBytes(dir / "frame_0002.exr");
  putInt(b, attributeValue(b, "dataWindow", "box2i") - 4, 840000000);
  writeBytes(dir / "frame_0002.exr", b);
  auto seq = SequenceReader::open(dir);
  const std::string msg = test::errorOf([&] { seq->read(1); });
  EXPECT_NE(msg.find("frame_0002.exr"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'dataWindow' claims 840000000 bytes"), std::string::npos) << msg;
  fs::remove_all(dir);
}

TEST(UntrustedFiles, NonRegularFilesAreRefusedWithoutBlocking) {
  const fs::path dir = test::scratchDir("rtd_untrusted", "fifo");
  ASSERT_EQ(::mkfifo((dir / "frame_0001.exr").c_str(), 0600), 0);  // reading it would block for ever
  const std::string msg = test::errorOf([&] { readRgbExr(dir / "frame_0001.exr"); });
  EXPECT_NE(msg.find("not a regular file"), std::string::npos) << msg;
  fs::create_directories(dir / "d.exr");
  EXPECT_NE(test::errorOf([&] { readRgbExr(dir / "d.exr"); }).find("not a regular file"), std::string::npos);
  fs::remove_all(dir);
}

// Reading stops at the deadline (a zero limit here) with the file's name.
TEST(UntrustedFiles, ReadDeadlineNamesTheFile) {
  const exr::ReadDeadline deadline("file 'slow.exr'", std::chrono::seconds(-1));
  const std::string msg = test::errorOf([&] { deadline.check(); });
  EXPECT_NE(msg.find("slow.exr"), std::string::npos) << msg;
  EXPECT_NE(msg.find("longer than"), std::string::npos) << msg;
  EXPECT_EQ(test::errorOf([] { exr::ReadDeadline("file 'fast.exr'").check(); }), "");
}

}  // namespace
}  // namespace rtd
