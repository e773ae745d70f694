// Per-buffer input files (issue 14 item 11): the same frames as a native sequence, written one
// file per buffer per frame in EXR, PFM (written here from its definition: a "PF"/"Pf" header,
// rows from the bottom, little-endian floats with a negative scale) and float TIFF, read back
// bit-exactly and denoised to the same result; lossy HDR and 8-bit PNG within their
// quantisation; pack builds the native sequence and names what is missing; bad layouts are
// refused naming the frame and buffer.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/exr.h"
#include "io/image_file.h"
#include "passes/tonemap.h"
#include "rtd/rtd.h"
#include "support/run_cli.h"
#include "synthetic/synthetic.h"
#include "support/files.h"

namespace rtd {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 3;

synthetic::Scene perBufferScene() {
  synthetic::Scene s;
  s.width = 24;
  s.height = 16;
  return s;
}

std::string fileName(Buffer b, int number, const std::string& ext) {
  char digits[16];
  std::snprintf(digits, sizeof digits, "%04d", number);
  return std::string(bufferName(b)) + "_" + digits + "." + ext;
}

/// EXR channel names of a buffer in a per-buffer file: R,G,B / X,Y,Z / X,Y / its one letter.
std::vector<std::string> exrNames(Buffer b) {
  const std::string_view layout = bufferChannels(b);
  if (layout == "RGB") return {"R", "G", "B"};
  if (layout == "I") return {"id"};
  std::vector<std::string> names;
  for (char c : layout) names.emplace_back(1, c);
  return names;
}

void writeExr(const fs::path& path, const Image& img, const std::vector<std::string>& names) {
  std::vector<exr::ChannelSource> ch;
  for (size_t c = 0; c < names.size(); ++c) ch.push_back({names[c], img.pixels.data() + c, size_t(img.channels)});
  exr::writeChannels(path, img.width, img.height, ch);
}

/// PFM by its definition: "PF" (3 channels) or "Pf" (1), "width height", a negative scale for
/// little-endian, then rows from the bottom of the image to the top.
void writePfm(const fs::path& path, const Image& img) {
  const int c = img.channels == 1 ? 1 : 3;
  std::ofstream out(path, std::ios::binary);
  out << (c == 3 ? "PF" : "Pf") << "\n" << img.width << " " << img.height << "\n-1.0\n";
  for (int y = img.height - 1; y >= 0; --y)
    for (int x = 0; x < img.width; ++x)
      for (int k = 0; k < c; ++k) {
        const float v = k < img.channels ? img.at(x, y, k) : 0.0f;  // motion's X, Y and a zero
        out.write(reinterpret_cast<const char*>(&v), sizeof v);
      }
}

/// Conversions by oiiotool, all in one run (each run loads OpenImageIO anew): input, the
/// arguments before -o, output.
struct Conversion {
  fs::path in;
  std::string args;
  fs::path out;
};
void oiiotool(const std::vector<Conversion>& conversions) {
  std::string cmd = "oiiotool";
  for (const auto& c : conversions) cmd.append(" ").append(c.in.string()).append(" ").append(c.args).append(" -o ").append(c.out.string());
  cmd += " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd << " (apt-get install openimageio-tools)";
}

void writeCameras(const fs::path& dir) {
  nlohmann::json cams = nlohmann::json::array();
  for (int k = 0; k < kFrames; ++k) {
    const Frame f = synthetic::makeFrame(perBufferScene(), k);
    cams.push_back({{"frame", f.number}, {"world_to_camera", f.camera.worldToCamera}, {"projection", f.camera.projection}});
  }
  std::ofstream(dir / "cameras.json") << nlohmann::json{{"cameras", cams}}.dump();
}

/// The synthetic frames one file per buffer: `ext` "exr", "pfm" or "tif" (float TIFF from the
/// EXR by oiiotool), and cameras.json.
fs::path writePerBuffer(const std::string& ext) {
  const fs::path dir = test::scratchDir("rtd_perbuffer", ext);
  std::vector<Conversion> tiffs;
  for (int k = 0; k < kFrames; ++k) {
    const Frame f = synthetic::makeFrame(perBufferScene(), k);
    for (int b = 0; b < kBufferCount; ++b) {
      if (!f.has(Buffer(b))) continue;
      const fs::path exr = dir / fileName(Buffer(b), f.number, "exr");
      if (ext == "pfm") {
        writePfm(dir / fileName(Buffer(b), f.number, "pfm"), f.buffers[b]);
        continue;
      }
      writeExr(exr, f.buffers[b], exrNames(Buffer(b)));
      if (ext == "tif") tiffs.push_back({exr, "-d float", dir / fileName(Buffer(b), f.number, "tif")});
    }
  }
  if (!tiffs.empty()) {
    oiiotool(tiffs);
    for (const auto& c : tiffs) fs::remove(c.in);
  }
  writeCameras(dir);
  return dir;
}

fs::path writeNative() {
  const fs::path dir = test::scratchDir("rtd_perbuffer", "native");
  SequenceWriter writer(dir);
  for (int k = 0; k < kFrames; ++k) writer.write(synthetic::makeFrame(perBufferScene(), k));
  writer.finish();
  return dir;
}

std::vector<Image> denoiseAll(const fs::path& dir) {
  auto seq = SequenceReader::open(dir);
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto d = device->createDenoiser("svgf");
  std::vector<Image> out;
  for (int i = 0; i < seq->frameCount(); ++i) {
    const Frame f = seq->read(i);
    out.emplace_back(f.width, f.height, 3);
    d->denoise(f.inputs(), out.back().view());
  }
  return out;
}

/// Formats other than EXR need librtdenoise_oiio: built with OpenImageIO, it must load.
#ifdef RTD_TEST_HAVE_OIIO
#define REQUIRE_OTHER_FORMATS() ASSERT_TRUE(io::otherFormatsAvailable()) << "librtdenoise_oiio.so did not load"
#else
#define REQUIRE_OTHER_FORMATS() GTEST_SKIP() << "built without OpenImageIO (apt-get install libopenimageio-dev)"
#endif

class PerBufferLossless : public ::testing::TestWithParam<std::string> {};

TEST_P(PerBufferLossless, ReadsTheNativeFramesAndDenoisesToTheSameResult) {
  if (GetParam() != "exr") { REQUIRE_OTHER_FORMATS(); }
  const fs::path native = writeNative(), dir = writePerBuffer(GetParam());
  auto seq = SequenceReader::open(dir), ref = SequenceReader::open(native);
  EXPECT_EQ(seq->kind(), SequenceKind::PerBuffer);
  EXPECT_EQ(seq->buffers().size(), ref->buffers().size());
  ASSERT_EQ(seq->frameCount(), kFrames);
  for (int i = 0; i < kFrames; ++i) {
    const Frame got = seq->read(i), want = ref->read(i);
    EXPECT_EQ(got.number, want.number);
    for (int b = 0; b < kBufferCount; ++b) {
      ASSERT_EQ(got.has(Buffer(b)), want.has(Buffer(b))) << bufferName(Buffer(b));
      if (want.has(Buffer(b))) { EXPECT_EQ(got.buffers[b].pixels, want.buffers[b].pixels) << bufferName(Buffer(b)); }
    }
    EXPECT_TRUE(got.camera.valid);
    EXPECT_EQ(got.camera.worldToCamera, want.camera.worldToCamera);
    EXPECT_EQ(got.camera.projection, want.camera.projection);
  }
  const auto a = denoiseAll(dir), b = denoiseAll(native);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].pixels, b[i].pixels) << "frame index " << i;
  fs::remove_all(dir);
  fs::remove_all(native);
}

INSTANTIATE_TEST_SUITE_P(Formats, PerBufferLossless, ::testing::Values("exr", "pfm", "tif"));

// Radiance as Radiance HDR (RGBE: 8-bit mantissas sharing an exponent) and the albedo as an
// sRGB-encoded 8-bit PNG: each read within its quantisation, the PNG decoded from sRGB.
TEST(PerBuffer, LossyFormatsWithinTheirQuantisation) {
  REQUIRE_OTHER_FORMATS();
  const fs::path dir = writePerBuffer("exr");
  std::vector<Conversion> conversions;
  for (int k = 0; k < kFrames; ++k) {
    const Frame f = synthetic::makeFrame(perBufferScene(), k);
    const fs::path color = dir / fileName(Buffer::Color, f.number, "exr"), albedo = dir / fileName(Buffer::Albedo, f.number, "exr");
    conversions.push_back({color, "", dir / fileName(Buffer::Color, f.number, "hdr")});
    Image encoded = f[Buffer::Albedo];
    for (float& v : encoded.pixels) v = tonemap::srgbEncode(std::clamp(v, 0.0f, 1.0f));
    writeExr(albedo, encoded, {"R", "G", "B"});
    conversions.push_back({albedo, "-d uint8 --attrib oiio:ColorSpace sRGB", dir / fileName(Buffer::Albedo, f.number, "png")});
  }
  oiiotool(conversions);
  for (const auto& c : conversions) fs::remove(c.in);
  auto seq = SequenceReader::open(dir);
  for (int i = 0; i < kFrames; ++i) {
    const Frame got = seq->read(i), want = synthetic::makeFrame(perBufferScene(), i);
    const Image &c = got[Buffer::Color], &wc = want[Buffer::Color];
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        const float peak = std::max({wc.at(x, y, 0), wc.at(x, y, 1), wc.at(x, y, 2)});
        for (int ch = 0; ch < 3; ++ch) {
          ASSERT_NEAR(c.at(x, y, ch), wc.at(x, y, ch), peak / 128.0f + 1e-6f) << "colour at " << x << "," << y;
          const float a = got[Buffer::Albedo].at(x, y, ch), wa = std::clamp(want[Buffer::Albedo].at(x, y, ch), 0.0f, 1.0f);
          ASSERT_NEAR(tonemap::srgbEncode(a), tonemap::srgbEncode(wa), 0.5f / 255.0f + 1e-4f) << "albedo at " << x << "," << y;
        }
      }
  }
  fs::remove_all(dir);
}

TEST(PerBuffer, RefusesMissingFilesDuplicatesAndIntegerDepth) {
  const fs::path dir = writePerBuffer("exr");
  const int last = synthetic::makeFrame(perBufferScene(), kFrames - 1).number;
  fs::remove(dir / fileName(Buffer::Normal, last, "exr"));
  std::string e = test::errorOf([&] { SequenceReader::open(dir); });
  EXPECT_NE(e.find("frame " + std::to_string(last) + ": no file for buffer 'normal'"), std::string::npos) << e;
  fs::remove_all(dir);

  const fs::path dup = writePerBuffer("exr");
  const int first = synthetic::makeFrame(perBufferScene(), 0).number;
  fs::copy_file(dup / fileName(Buffer::Depth, first, "exr"), dup / fileName(Buffer::Depth, first, "pfm"));
  e = test::errorOf([&] { SequenceReader::open(dup); });
  EXPECT_NE(e.find("are both buffer 'depth' of frame " + std::to_string(first)), std::string::npos) << e;
  fs::remove(dup / fileName(Buffer::Depth, first, "pfm"));

  if (io::otherFormatsAvailable()) {
    const fs::path depth = dup / fileName(Buffer::Depth, first, "exr");
    oiiotool({{depth, "-d uint8", dup / fileName(Buffer::Depth, first, "png")}});
    fs::remove(depth);
    auto seq = SequenceReader::open(dup);
    e = test::errorOf([&] { seq->read(0); });
    EXPECT_NE(e.find("buffer 'depth'"), std::string::npos) << e;
    EXPECT_NE(e.find("an integer image"), std::string::npos) << e;
  }
  fs::remove_all(dup);
}

// pack turns the per-buffer files into a native sequence with the same frames and cameras, and
// says what the methods need that the input lacks.
TEST(PerBuffer, PackBuildsTheNativeSequenceAndNamesWhatIsMissing) {
  const fs::path dir = writePerBuffer("exr"), out = test::scratchDir("rtd_perbuffer", "packed");
  fs::remove_all(out);
  const auto r = test::runCli("pack -i " + dir.string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("cameras: every frame"), std::string::npos) << r.output;
  auto packed = SequenceReader::open(out), seq = SequenceReader::open(dir);
  EXPECT_EQ(packed->kind(), SequenceKind::Native);
  for (int i = 0; i < kFrames; ++i) {
    const Frame a = packed->read(i), b = seq->read(i);
    for (int k = 0; k < kBufferCount; ++k) EXPECT_EQ(a.buffers[k].pixels, b.buffers[k].pixels) << bufferName(Buffer(k));
    EXPECT_EQ(a.camera.worldToCamera, b.camera.worldToCamera);
  }
  // Colour alone: pack names the buffers the methods need.
  const fs::path colourOnly = test::scratchDir("rtd_perbuffer", "colour_only"), out2 = test::scratchDir("rtd_perbuffer", "packed2");
  for (int k = 0; k < kFrames; ++k) {
    const int n = synthetic::makeFrame(perBufferScene(), k).number;
    fs::copy_file(dir / fileName(Buffer::Color, n, "exr"), colourOnly / fileName(Buffer::Color, n, "exr"));
  }
  fs::remove_all(out2);
  const auto r2 = test::runCli("pack -i " + colourOnly.string() + " -o " + out2.string());
  ASSERT_EQ(r2.code, 0) << r2.output;
  EXPECT_NE(r2.output.find("missing normal (required by"), std::string::npos) << r2.output;
  EXPECT_NE(r2.output.find("cameras: none"), std::string::npos) << r2.output;
  for (const auto& p : {dir, out, colourOnly, out2}) fs::remove_all(p);
}

}  // namespace
}  // namespace rtd
