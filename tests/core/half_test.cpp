// Half floats on the host (Format::Half*): the conversions against hand-computed bit patterns
// and exhaustively against each other, import of half views (strided, sanitized) and half outputs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/frame_data.h"
#include "core/half.h"
#include "rtd/rtd.h"
#include "synthetic/synthetic.h"
#include "support/cpu_paths.h"

namespace rtd {
namespace {

TEST(Half, KnownValues) {
  // IEEE 754 binary16: sign, 5 exponent bits (bias 15), 10 mantissa bits.
  struct Case {
    uint16_t bits;
    float value;
  } cases[] = {{0x0000, 0.0f},          {0x3c00, 1.0f},          {0xc000, -2.0f},
               {0x3555, 0.333251953125f}, {0x7bff, 65504.0f},     {0x0400, 0x1p-14f},
               {0x0001, 0x1p-24f},      {0x03ff, 1023 * 0x1p-24f}, {0x7c00, INFINITY},
               {0xfc00, -INFINITY},     {0x3e00, 1.5f}};
  for (const auto& c : cases) {
    EXPECT_EQ(halfToFloat(c.bits), c.value) << std::hex << c.bits;
    EXPECT_EQ(floatToHalf(c.value), c.bits) << c.value;
  }
  EXPECT_EQ(floatToHalf(-0.0f), 0x8000);
  EXPECT_TRUE(std::isnan(halfToFloat(0x7e00)));
  EXPECT_EQ(floatToHalf(NAN) & 0x7c00, 0x7c00);
  EXPECT_NE(floatToHalf(NAN) & 0x03ff, 0);
}

TEST(Half, RoundsToNearestEven) {
  // Between 1 and 1 + 2^-10 (the next half): below, at and above the midpoint 1 + 2^-11.
  EXPECT_EQ(floatToHalf(1.0f + 0x1p-11f), 0x3c00);                 // tie: to the even 1.0
  EXPECT_EQ(floatToHalf(1.0f + 0x1p-11f + 0x1p-20f), 0x3c01);      // above: up
  EXPECT_EQ(floatToHalf(1.0f + 3 * 0x1p-11f), 0x3c02);             // tie between 0x3c01 and 0x3c02: even
  EXPECT_EQ(floatToHalf(65519.0f), 0x7bff);                        // below 65520: the largest half
  EXPECT_EQ(floatToHalf(65520.0f), 0x7c00);                        // the tie above 65504 rounds to infinity
  EXPECT_EQ(floatToHalf(1e10f), 0x7c00);
  EXPECT_EQ(floatToHalf(0x1p-25f), 0x0000);                        // tie between 0 and 2^-24: even 0
  EXPECT_EQ(floatToHalf(0x1p-25f * 1.5f), 0x0001);
  EXPECT_EQ(floatToHalf(3 * 0x1p-25f), 0x0002);                    // tie between 1 and 2 units: even 2
  EXPECT_EQ(floatToHalf(0x1p-14f - 0x1p-26f), 0x0400);             // rounds up into the normals
}

// Every half converts to a float and back to itself, through the scalar and the bulk paths
// alike (the bulk conversions on every CPU path this machine runs: scalar on sse2, F16C on
// avx2 and avx512); and the bulk float->half path rounds like the scalar one on values between
// halves.
TEST(Half, AllHalvesRoundTripOnEveryPath) {
  std::vector<uint16_t> halves(65536);
  for (int i = 0; i < 65536; ++i) halves[i] = uint16_t(i);
  std::vector<float> between;
  for (int i = 0; i < 0x7c00; i += 7) {
    const float a = halfToFloat(uint16_t(i)), b = halfToFloat(uint16_t(i + 1));
    between.push_back(0.5f * (a + b));              // the tie
    between.push_back(a + 0.3f * (b - a));
    between.push_back(-(a + 0.7f * (b - a)));
  }
  for (CpuPath path : test::supportedCpuPaths()) {
    SCOPED_TRACE(cpuPathName(path));
    test::ScopedCpuPath forced(path);
    std::vector<uint16_t> back(65536);
    std::vector<float> floats(65536);
    halvesToFloats(halves.data(), floats.data(), halves.size());
    floatsToHalves(floats.data(), back.data(), floats.size());
    for (int i = 0; i < 65536; ++i) {
      const float scalar = halfToFloat(uint16_t(i));
      if (std::isnan(scalar)) {
        EXPECT_TRUE(std::isnan(floats[i]));
        continue;
      }
      ASSERT_EQ(std::memcmp(&scalar, &floats[i], 4), 0) << i;
      ASSERT_EQ(back[i], i);
      ASSERT_EQ(floatToHalf(scalar), i);
    }
    std::vector<uint16_t> bulk(between.size());
    floatsToHalves(between.data(), bulk.data(), between.size());
    for (size_t i = 0; i < between.size(); ++i) ASSERT_EQ(bulk[i], floatToHalf(between[i])) << between[i];
  }
}

// A Half3 view inside Half4-strided, padded rows (at an odd 2-byte offset) imports exactly the
// halves' values; NaN, infinity and (for radiance) negatives become 0 and are counted.
TEST(Half, ImportOfStridedHalfViews) {
  const int w = 13, h = 5, pixelStride = 8, rowStride = w * pixelStride + 6;
  std::vector<char> storage(size_t(rowStride) * h + 2);
  char* base = storage.data() + 2;
  Image expected(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = 0.01f * float(x * 7 + y * 3 + c) + 0.001f;
        const uint16_t bits = floatToHalf(v);
        std::memcpy(base + size_t(y) * rowStride + size_t(x) * pixelStride + 2 * c, &bits, 2);
        expected.at(x, y, c) = halfToFloat(bits);
      }
  const uint16_t nan = 0x7e00, inf = 0x7c00, negative = floatToHalf(-1.0f);
  std::memcpy(base + 2 * pixelStride, &nan, 2);
  std::memcpy(base + rowStride + 2, &inf, 2);
  std::memcpy(base + 2 * rowStride + 4, &negative, 2);
  expected.at(2, 0, 0) = 0;
  expected.at(0, 1, 1) = 0;
  expected.at(0, 2, 2) = 0;

  FrameInputs in;
  in[Buffer::Color] = {base, w, h, Format::Half3, size_t(pixelStride), size_t(rowStride)};
  FrameData d;
  EXPECT_EQ(importFrame(in, {Buffer::Color}, d), 3u);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(d.plane(Buffer::Color, c)(x, y), expected.at(x, y, c)) << x << "," << y;
}

// The same frames given as Float and as Half views of the same (half-representable) values give
// the same output bit for bit, and a Half4 output holds the Float4 output rounded to halves.
TEST(Half, HalfInputsAndOutputsMatchFloatOnes) {
  synthetic::Scene scene;
  scene.width = 40;
  scene.height = 24;
  auto device = Device::create();
  auto asFloat = device->createDenoiser("svgf"), asHalf = device->createDenoiser("svgf");
  for (int i = 0; i < 4; ++i) {
    Frame f = synthetic::makeFrame(scene, i);
    std::array<std::vector<uint16_t>, kBufferCount> halves;
    FrameInputs half = f.inputs();
    for (int b = 0; b < kBufferCount; ++b) {
      Image& img = f.buffers[b];
      if (img.empty() || Buffer(b) == Buffer::ObjectId) continue;
      halves[b].resize(img.pixels.size());
      floatsToHalves(img.pixels.data(), halves[b].data(), img.pixels.size());
      halvesToFloats(halves[b].data(), img.pixels.data(), img.pixels.size());  // the float frame holds the same values
      static constexpr Format kHalf[] = {Format::Undefined, Format::Half, Format::Half2, Format::Half3, Format::Half4};
      half.buffers[b] = {halves[b].data(), img.width, img.height, kHalf[img.channels], 0, 0};
    }
    Image floatOut(scene.width, scene.height, 4);
    std::vector<uint16_t> halfOut(size_t(scene.width) * scene.height * 4);
    asFloat->denoise(f.inputs(), floatOut.view());
    asHalf->denoise(half, {halfOut.data(), scene.width, scene.height, Format::Half4});
    for (size_t k = 0; k < halfOut.size(); ++k) ASSERT_EQ(halfOut[k], floatToHalf(floatOut.pixels[k])) << "frame " << i;
  }
}

}  // namespace
}  // namespace rtd
