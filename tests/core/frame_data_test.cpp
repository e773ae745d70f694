// Frame import and export. Import: every layout the API accepts (1-4 packed float channels, a
// wider pixel stride, integer ids) de-interleaves into planes with non-finite values replaced,
// and radiance also with negatives replaced. Export: planes (plus emission) interleave into
// Float3 / Float4 views, packed or with a wider pixel stride. Checked value by value against
// the definitions, on widths that are not a multiple of the eight-pixel vector path and on a
// frame large enough to be written with streaming stores.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "core/frame_data.h"

namespace rtd {
namespace {

// A value drawn so that every kind the sanitization distinguishes occurs often.
float drawValue(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  switch (rng() % 10) {
    case 0: return std::numeric_limits<float>::quiet_NaN();
    case 1: return (rng() & 1) ? INFINITY : -INFINITY;
    case 2: return (rng() & 1) ? 3.4e38f : -3.4e38f;  // finite, but beyond the accepted range
    default: return u(rng);
  }
}

float expected(float v, bool radiance) {
  const bool ok = std::isfinite(v) && std::abs(v) <= 3.0e38f && (!radiance || v >= 0.0f);
  return ok ? v : 0.0f;
}

struct Layout {
  Buffer buffer;
  int floatsPerPixel;  // the view's pixel stride in floats (>= the buffer's channel count)
};

TEST(FrameImport, DeinterleavesAndSanitizesEveryPackedLayout) {
  std::mt19937 rng(7);
  const Layout layouts[] = {
      {Buffer::Depth, 1},  {Buffer::Motion, 2}, {Buffer::Color, 3},  {Buffer::Normal, 3},
      {Buffer::Color, 4},  {Buffer::Albedo, 4}, {Buffer::Motion, 4}, {Buffer::Position, 5},
  };
  for (const Layout& layout : layouts)
    for (int w : {1, 7, 8, 29}) {
      const int h = 3, channels = bufferChannelCount(layout.buffer), n = layout.floatsPerPixel;
      std::vector<float> data(size_t(w) * h * n);
      for (float& v : data) v = drawValue(rng);
      FrameInputs in;
      std::vector<float> color(size_t(w) * h * 3, 0.5f);
      in[Buffer::Color] = ImageView{color.data(), w, h, Format::Float3};
      const Format format = n == 1 ? Format::Float : n == 2 ? Format::Float2 : n == 3 ? Format::Float3 : Format::Float4;
      in[layout.buffer] = ImageView{data.data(), w, h, format, size_t(n) * 4};
      FrameData out;
      const uint64_t replaced = importFrame(in, {Buffer::Color}, out);
      const bool radiance = isRadianceBuffer(layout.buffer);
      uint64_t expectedReplaced = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < channels; ++c) {
            const float v = data[(size_t(y) * w + x) * n + c], e = expected(v, radiance);
            expectedReplaced += !(e == v);
            ASSERT_EQ(out.plane(layout.buffer, c)(x, y), e)
                << bufferName(layout.buffer) << " stride " << n << " width " << w << " at " << x << "," << y << " channel " << c;
          }
      EXPECT_EQ(replaced, expectedReplaced) << bufferName(layout.buffer) << " stride " << n << " width " << w;
    }
}

// Frames larger than the cache are written with streaming stores: the same values.
TEST(FrameImport, LargeFramesGiveTheSameValues) {
  std::mt19937 rng(11);
  const int w = 1280, h = 720;
  std::vector<float> color(size_t(w) * h * 3), normal(size_t(w) * h * 3);
  for (float& v : color) v = drawValue(rng);
  for (float& v : normal) v = drawValue(rng);
  FrameInputs in;
  in[Buffer::Color] = ImageView{color.data(), w, h, Format::Float3};
  in[Buffer::Normal] = ImageView{normal.data(), w, h, Format::Float3};
  FrameData out;
  importFrame(in, {Buffer::Color}, out);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const size_t i = (size_t(y) * w + x) * 3 + c;
        ASSERT_EQ(out.plane(Buffer::Color, c)(x, y), expected(color[i], true)) << x << "," << y;
        ASSERT_EQ(out.plane(Buffer::Normal, c)(x, y), expected(normal[i], false)) << x << "," << y;
      }
}

TEST(FrameImport, ConvertsIntegerIds) {
  const int w = 11, h = 2;
  std::vector<int32_t> ids(size_t(w) * h);
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = int32_t(i * 37) - 100;
  std::vector<float> color(size_t(w) * h * 3, 1.0f);
  FrameInputs in;
  in[Buffer::Color] = ImageView{color.data(), w, h, Format::Float3};
  in[Buffer::ObjectId] = ImageView{ids.data(), w, h, Format::Int32};
  FrameData out;
  EXPECT_EQ(importFrame(in, {Buffer::Color}, out), 0u);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) EXPECT_EQ(out.plane(Buffer::ObjectId)(x, y), float(ids[size_t(y) * w + x]));
}

TEST(FrameExport, InterleavesEveryOutputLayout) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 4.0f);
  for (int w : {1, 7, 8, 29, 1280})
    for (Format format : {Format::Float3, Format::Float4})
      for (int extraFloats : {0, 1})  // packed, or a wider pixel stride
        for (bool withEmission : {false, true}) {
          const int h = w == 1280 ? 720 : 3;
          Plane3 rgb;
          std::vector<Plane> emission(3);
          for (int c = 0; c < 3; ++c) {
            rgb[c].resize(w, h);
            emission[size_t(c)].resize(w, h);
            for (float& v : rgb[c].data) v = u(rng);
            for (float& v : emission[size_t(c)].data) v = u(rng);
          }
          const int stride = channelCount(format) + extraFloats;
          // 32-byte aligned, so the large frame takes the streaming stores
          std::vector<float> storage(size_t(w) * h * stride + 8, -7.0f);
          float* out = storage.data() + (8 - reinterpret_cast<uintptr_t>(storage.data()) % 32 / 4) % 8;
          exportRgb(rgb, withEmission ? &emission : nullptr, ImageView{out, w, h, format, size_t(stride) * 4});
          for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
              const float* p = out + (size_t(y) * w + x) * stride;
              for (int c = 0; c < 3; ++c) {
                const float e = withEmission ? rgb[c](x, y) + emission[size_t(c)](x, y) : rgb[c](x, y);
                ASSERT_EQ(p[c], e) << "width " << w << " stride " << stride << " at " << x << "," << y << " channel " << c;
              }
              if (format == Format::Float4) {
                ASSERT_EQ(p[3], 1.0f);
              }
              if (extraFloats) {
                ASSERT_EQ(p[stride - 1], -7.0f) << "wrote past the pixel";
              }
            }
        }
}

}  // namespace
}  // namespace rtd
