// Frame import and export. Import: every layout the API accepts (1-4 packed float channels, a
// wider pixel stride, integer ids) de-interleaves into planes with non-finite values replaced
// by 0, finite ones clamped into their buffer's range and normals renormalized, counted per
// buffer. Export: planes (plus emission) interleave into
// Float3 / Float4 views, packed or with a wider pixel stride. Checked value by value against
// the definitions, on widths that are not a multiple of the eight-pixel vector path and on a
// frame large enough to be written with streaming stores.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <array>
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
    case 2: return (rng() & 1) ? 3.4e38f : -3.4e38f;  // finite, but beyond every buffer's range
    case 3: return (rng() & 1) ? 1e30f : 7e4f;        // beyond the radiance bound only
    default: return u(rng);
  }
}

// The documented range of each buffer tested here (docs/input-validation.md).
std::pair<float, float> rangeOf(Buffer b) {
  switch (b) {
    case Buffer::Color: case Buffer::Albedo: return {0.0f, 65504.0f};
    case Buffer::Depth: return {0.0f, 1e18f};
    case Buffer::Motion: return {-16777216.0f, 16777216.0f};
    default: return {-1e18f, 1e18f};  // normal, position
  }
}

// NaN and Inf become 0, finite values are clamped into the range.
float expected(float v, Buffer b) {
  if (!std::isfinite(v)) return 0.0f;
  const auto [lo, hi] = rangeOf(b);
  return std::min(std::max(v, lo), hi);
}

struct Layout {
  Buffer buffer;
  int floatsPerPixel;  // the view's pixel stride in floats (>= the buffer's channel count)
};

// Normals after import: the sanitized vector, divided by its length (computed in double) unless
// it is (0, 0, 0) or within 1e-3 of unit squared length.
std::array<double, 3> expectedNormal(const float* v) {
  std::array<double, 3> n;
  for (int c = 0; c < 3; ++c) n[size_t(c)] = expected(v[c], Buffer::Normal);
  const double l2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  if (l2 == 0.0 || std::abs(l2 - 1.0) <= 1e-3) return n;
  for (double& c : n) c /= std::sqrt(l2);
  return n;
}

TEST(FrameImport, DeinterleavesAndSanitizesEveryPackedLayout) {
  std::mt19937 rng(7);
  const Layout layouts[] = {
      {Buffer::Depth, 1},  {Buffer::Motion, 2}, {Buffer::Color, 3},  {Buffer::Normal, 3},
      {Buffer::Color, 4},  {Buffer::Albedo, 4}, {Buffer::Motion, 4}, {Buffer::Position, 5},
      {Buffer::Normal, 4},
  };
  for (const Layout& layout : layouts)
    for (int w : {1, 7, 8, 29, 45}) {  // the 16-, 8-pixel and scalar loops and their seams
      const int h = 3, channels = bufferChannelCount(layout.buffer), n = layout.floatsPerPixel;
      std::vector<float> data(size_t(w) * h * n);
      for (float& v : data) v = drawValue(rng);
      FrameInputs in;
      std::vector<float> color(size_t(w) * h * 3, 0.5f);
      in[Buffer::Color] = ImageView{color.data(), w, h, Format::Float3};
      const Format format = n == 1 ? Format::Float : n == 2 ? Format::Float2 : n == 3 ? Format::Float3 : Format::Float4;
      in[layout.buffer] = ImageView{data.data(), w, h, format, size_t(n) * 4};
      FrameData out;
      SanitizeStats counts;
      const uint64_t replaced = importFrame(in, {Buffer::Color}, out, nullptr, &counts);
      SanitizeCounts expectedCounts;
      const bool normal = layout.buffer == Buffer::Normal;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const float* v = &data[(size_t(y) * w + x) * n];
          for (int c = 0; c < channels; ++c) {
            expectedCounts.nonFinite += !std::isfinite(v[c]);
            expectedCounts.outOfRange += std::isfinite(v[c]) && expected(v[c], layout.buffer) != v[c];
          }
          const std::string where = std::string(bufferName(layout.buffer)) + " stride " + std::to_string(n) + " width " +
                                    std::to_string(w) + " at " + std::to_string(x) + "," + std::to_string(y);
          if (normal) {
            const auto e = expectedNormal(v);
            bool changed = false;
            for (int c = 0; c < 3; ++c) changed |= e[size_t(c)] != double(expected(v[c], Buffer::Normal));
            expectedCounts.renormalized += changed;
            for (int c = 0; c < 3; ++c)
              ASSERT_NEAR(out.plane(layout.buffer, c)(x, y), e[size_t(c)], 1e-6) << where << " channel " << c;
          } else {
            for (int c = 0; c < channels; ++c)
              ASSERT_EQ(out.plane(layout.buffer, c)(x, y), expected(v[c], layout.buffer)) << where << " channel " << c;
          }
        }
      const SanitizeCounts& got = counts[size_t(layout.buffer)];
      EXPECT_EQ(got.nonFinite, expectedCounts.nonFinite) << bufferName(layout.buffer) << " width " << w;
      EXPECT_EQ(got.outOfRange, expectedCounts.outOfRange) << bufferName(layout.buffer) << " width " << w;
      EXPECT_EQ(got.renormalized, expectedCounts.renormalized) << bufferName(layout.buffer) << " width " << w;
      EXPECT_EQ(replaced, expectedCounts.total()) << bufferName(layout.buffer) << " stride " << n << " width " << w;
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
        ASSERT_EQ(out.plane(Buffer::Color, c)(x, y), expected(color[i], Buffer::Color)) << x << "," << y;
        ASSERT_NEAR(out.plane(Buffer::Normal, c)(x, y), expectedNormal(&normal[i - size_t(c)])[size_t(c)], 1e-6) << x << "," << y;
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

namespace rtd {
namespace {

// World positions cost 12 bytes a pixel to import: they are imported for the reprojection's
// position test and where the frame has no motion vectors (the previous camera projects them
// instead), not otherwise; the method's own lists still bring them in.
TEST(FrameImport, WorldPositionsOnlyWhereTheReprojectionUsesThem) {
  auto has = [](const std::vector<Buffer>& list, Buffer b) { return std::find(list.begin(), list.end(), b) != list.end(); };
  const std::vector<Buffer> required = {Buffer::Color};
  ReprojectionSettings plain;
  EXPECT_FALSE(has(importedBuffers(required, {}, plain, true), Buffer::Position));
  EXPECT_TRUE(has(importedBuffers(required, {}, plain, false), Buffer::Position));
  EXPECT_TRUE(has(importedBuffers(required, {Buffer::Position}, plain, true), Buffer::Position));
  ReprojectionSettings tested;
  tested.positionFootprints = 4.0f;
  EXPECT_TRUE(has(importedBuffers(required, {}, tested, true), Buffer::Position));
  tested.positionFootprints = 0.0f;
  tested.positionTolerance = 0.04f;
  EXPECT_TRUE(has(importedBuffers(required, {}, tested, true), Buffer::Position));
  EXPECT_TRUE(has(importedBuffers(required, {}, plain, true), Buffer::Motion));
}

}  // namespace
}  // namespace rtd
