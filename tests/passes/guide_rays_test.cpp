// Supersampling with guide rays (Voorhuis 2018, Sec. 5; checklist item 22): energy under any
// spp, assignment across a depth edge and anti-aliased coverage, the 1/(1 + |A|) variance of
// the pre-mixed input, Eq. 7 by hand, and errors for malformed samples.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "passes/guide_rays_fixtures.h"
#include "rtd/guide_rays.h"
#include "rtd/rtd.h"

namespace rtd {
namespace {
using test::guideFrame;
using test::samplesAt;

TEST(GuideRays, ConstantRadianceKeepsItsEnergyForAnySampleCount) {
  // Checklist 22 (a): whatever the assignment, Eq. 7 averages equal values and the copy back
  // averages equal values: a constant image stays exactly constant, for 1 to 8 spp.
  const int w = 24, h = 16;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f), z(1.0f, 3.0f);
  for (int spp : {1, 2, 4, 8}) {
    const Frame g = guideFrame(w, h, [&](float, float) { return z(rng); }, 0.37f);
    const GuideRaySamples s = samplesAt(
        w, h, spp - 1, [&](int, int, int) { return std::pair{u(rng), u(rng)}; }, [&](float, float) { return z(rng); },
        [](float, float) { return 0.37f; });
    GuideRays gr;
    const Frame mixed = gr.premix(g, s);
    for (float v : mixed[Buffer::Color].pixels) ASSERT_NEAR(v, 0.37f, 1e-6f) << spp << " spp";
    const Image out = gr.resolve(mixed[Buffer::Color]);
    for (float v : out.pixels) ASSERT_NEAR(v, 0.37f, 1e-6f) << spp << " spp";
  }
}

TEST(GuideRays, ConstantRadianceThroughSvgfKeepsItsEnergy) {
  // The whole chain, pre-mix -> SVGF (Voorhuis preset, TAA off as in the paper's supersampling
  // tests) -> copy back, over 4 frames: a constant image is SVGF's fixed point, so it stays.
  const int w = 32, h = 20;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f), z(1.0f, 1.5f);
  auto device = Device::create();
  auto d = device->createDenoiser("svgf");
  d->set("variant", "voorhuis");
  d->set("taa", "false");
  for (int frame = 0; frame < 4; ++frame) {
    Frame g = guideFrame(w, h, [&](float x, float y) { return 1.0f + 0.01f * x + 0.02f * y; }, 0.42f);
    g[Buffer::Albedo] = Image(w, h, 3, 0.8f);
    g[Buffer::Motion] = Image(w, h, 2);
    const GuideRaySamples s = samplesAt(
        w, h, 3, [&](int, int, int) { return std::pair{u(rng), u(rng)}; }, [&](float, float) { return z(rng); },
        [](float, float) { return 0.42f; });
    GuideRays gr;
    const Frame mixed = gr.premix(g, s);
    Image out(w, h, 3);
    d->denoise(mixed.inputs(), out.view());
    const Image resolved = gr.resolve(out);
    for (float v : resolved.pixels) ASSERT_NEAR(v, 0.42f, 1e-4f) << "frame " << frame;
  }
}

TEST(GuideRays, Eq7AveragesTheSamplesAGuideReceives) {
  // 2x1 image, one non-guide sample per pixel. Guide depths 1 (left) and 2 (right). The left
  // pixel's sample lies right of its centre at depth 2: it joins the right guide. The right
  // pixel's sample lies left of its centre at depth 2: it joins its own guide.
  const Frame g = guideFrame(2, 1, [](float x, float) { return x < 0.5f ? 1.0f : 2.0f; }, 0.0f);
  Frame guides = g;
  guides[Buffer::Color].at(0, 0, 0) = 1.0f;
  guides[Buffer::Color].at(1, 0, 0) = 2.0f;
  GuideRaySamples s = samplesAt(
      2, 1, 1, [](int, int x, int) { return x == 0 ? std::pair{0.4f, 0.0f} : std::pair{-0.3f, 0.0f}; },
      [](float, float) { return 2.0f; }, [](float, float) { return 0.0f; });
  s.samples[0][Buffer::Color].at(0, 0, 0) = 10.0f;
  s.samples[0][Buffer::Color].at(1, 0, 0) = 20.0f;
  GuideRays gr;
  const Frame mixed = gr.premix(guides, s);
  EXPECT_EQ(gr.assignedGuide(1, 0), 1);
  EXPECT_EQ(gr.assignedGuide(1, 1), 1);
  EXPECT_EQ(gr.mixCount()[0], 1);
  EXPECT_EQ(gr.mixCount()[1], 3);
  EXPECT_FLOAT_EQ(mixed[Buffer::Color].at(0, 0, 0), 1.0f);                   // nothing joined
  EXPECT_FLOAT_EQ(mixed[Buffer::Color].at(1, 0, 0), (2.0f + 10.0f + 20.0f) / 3);  // Eq. 7
  // Post-filter copy: pixel 0 = (its guide + the right guide) / 2, pixel 1 = its guide twice.
  Image filtered(2, 1, 3);
  filtered.at(0, 0, 0) = 4.0f;
  filtered.at(1, 0, 0) = 8.0f;
  const Image out = gr.resolve(filtered);
  EXPECT_FLOAT_EQ(out.at(0, 0, 0), 6.0f);
  EXPECT_FLOAT_EQ(out.at(1, 0, 0), 8.0f);
}

TEST(GuideRays, SamplesAcrossADiagonalEdgeJoinTheirOwnSurfaceAndAntiAlias) {
  // Checklist 22 (b): two planes, the near one (depth 1, colour 1) below the line
  // x + 0.7 y = 20, the far one (depth 3, colour 0) above it. 15 jittered samples on a 4x4
  // stratified grid per pixel. Every sample joins a guide on its own plane (one of the four
  // corners of its cell is always on its side of a straight edge), so with an identity
  // "filter" each pixel becomes the share of its samples on the near plane: close to the
  // pixel's exact area coverage, where the guides alone give 0 or 1.
  const int w = 40, h = 24;
  auto near = [](float x, float y) { return x + 0.7f * y < 20.0f; };  // x, y: pixel-centre coordinates
  auto depth = [&](float x, float y) { return near(x, y) ? 1.0f : 3.0f; };
  const Frame g = guideFrame(w, h, depth, 0.0f);
  Frame guides = g;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) guides[Buffer::Color].at(x, y, c) = near(float(x), float(y)) ? 1.0f : 0.0f;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const GuideRaySamples s = samplesAt(
      w, h, 15, [&](int k, int, int) { return std::pair{((k % 4) + u(rng)) / 4 - 0.5f, ((k / 4) + u(rng)) / 4 - 0.5f}; },
      depth, [&](float x, float y) { return near(x, y) ? 1.0f : 0.0f; });
  GuideRays gr;
  const Frame mixed = gr.premix(guides, s);
  for (int k = 1; k <= 15; ++k)
    for (int i = 0; i < w * h; ++i) {
      const float zs = s.samples[size_t(k - 1)][Buffer::Depth].pixels[size_t(i)];
      ASSERT_EQ(g[Buffer::Depth].pixels[size_t(gr.assignedGuide(k, i))], zs) << "sample " << k << " of pixel " << i;
    }
  const Image out = gr.resolve(mixed[Buffer::Color]);
  // Exact coverage of each pixel's area by the near plane, by a 64x64 grid.
  double errAa = 0, errGuides = 0;
  int edge = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int in = 0;
      for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) in += near(x - 0.5f + (i + 0.5f) / 64, y - 0.5f + (j + 0.5f) / 64);
      const double cover = in / 4096.0;
      if (cover == 0 || cover == 1) {
        ASSERT_FLOAT_EQ(out.at(x, y), float(cover)) << x << "," << y;  // inside a plane: unchanged
        continue;
      }
      ++edge;
      errAa += std::abs(out.at(x, y) - cover);
      errGuides += std::abs(guides[Buffer::Color].at(x, y) - cover);
    }
  ASSERT_GT(edge, 20);
  errAa /= edge;
  errGuides /= edge;
  EXPECT_LT(errAa, 0.08) << "edge pixels " << edge;
  EXPECT_LT(errAa, 0.3 * errGuides);
}

TEST(GuideRays, PremixedVarianceFallsAsOneOverOnePlusTheJoinedSamples) {
  // Checklist 22 (c): i.i.d. radiance of variance s^2 per sample. Each sample's depth equals
  // that of one random guide of its cell, so it joins that guide and guides receive 0 to ~12
  // samples. Per count m = 1 + |A|, the pre-mixed radiance's variance is s^2 / m.
  const int w = 128, h = 128, n = 3;
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.5f, 0.2f);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f), z(1.0f, 2.0f);
  std::vector<float> gz(size_t(w) * h);
  for (float& v : gz) v = z(rng);
  Frame g = guideFrame(w, h, [&](float x, float y) { return gz[size_t(y) * w + size_t(x)]; }, 0.0f);
  for (float& v : g[Buffer::Color].pixels) v = noise(rng);
  GuideRaySamples s = samplesAt(
      w, h, n, [&](int, int, int) { return std::pair{u(rng), u(rng)}; }, [](float, float) { return 0.0f; },
      [&](float, float) { return 0.0f; });
  for (int k = 0; k < n; ++k)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float px = x + s.offsets[size_t(k)].at(x, y, 0), py = y + s.offsets[size_t(k)].at(x, y, 1);
        int qx = int(std::floor(px)) + int(rng() % 2), qy = int(std::floor(py)) + int(rng() % 2);
        qx = std::clamp(qx, 0, w - 1);
        qy = std::clamp(qy, 0, h - 1);
        s.samples[size_t(k)][Buffer::Depth].at(x, y) = gz[size_t(qy) * w + size_t(qx)];
        for (int c = 0; c < 3; ++c) s.samples[size_t(k)][Buffer::Color].at(x, y, c) = noise(rng);
      }
  GuideRays gr;
  const Frame mixed = gr.premix(g, s);
  std::map<int, std::pair<double, double>> moments;  // m -> (sum, sum of squares) over values
  std::map<int, int> count;
  for (int i = 0; i < w * h; ++i) {
    const int m = gr.mixCount()[size_t(i)];
    for (int c = 0; c < 3; ++c) {
      const double v = mixed[Buffer::Color].pixels[size_t(i) * 3 + c];
      moments[m].first += v;
      moments[m].second += v * v;
      ++count[m];
    }
  }
  int checked = 0;
  for (const auto& [m, sums] : moments) {
    if (count[m] < 3000) continue;
    const double mean = sums.first / count[m], var = sums.second / count[m] - mean * mean;
    EXPECT_NEAR(var * m / (0.2 * 0.2), 1.0, 0.12) << "m = " << m << ", " << count[m] << " values";
    ++checked;
  }
  EXPECT_GE(checked, 3);  // m = 1 .. at least 3 well-populated counts
}

TEST(GuideRays, GuidesOutsideTheImageAreNotCandidates) {
  // A corner pixel's sample pointing out of the image joins a guide inside it.
  const Frame g = guideFrame(3, 3, [](float, float) { return 1.0f; }, 0.0f);
  const GuideRaySamples s = samplesAt(
      3, 3, 1, [](int, int, int) { return std::pair{-0.5f, -0.5f}; }, [](float, float) { return 5.0f; },
      [](float, float) { return 0.0f; });
  GuideRays gr;
  gr.premix(g, s);
  for (int i = 0; i < 9; ++i) {
    const int a = gr.assignedGuide(1, i);
    EXPECT_GE(a, 0);
    EXPECT_LT(a, 9);
  }
  EXPECT_EQ(gr.assignedGuide(1, 0), 0);  // pixel (0, 0): its own guide is the only candidate
}

TEST(GuideRays, MalformedSamplesAreErrors) {
  const Frame g = guideFrame(4, 4, [](float, float) { return 1.0f; }, 0.0f);
  GuideRaySamples s = samplesAt(
      4, 4, 1, [](int, int, int) { return std::pair{0.0f, 0.0f}; }, [](float, float) { return 1.0f; },
      [](float, float) { return 0.0f; });
  GuideRays gr;
  EXPECT_THROW(gr.resolve(Image(4, 4, 3)), Error);  // before premix
  GuideRaySamples noDepth = s;
  noDepth.samples[0][Buffer::Depth] = Image();
  EXPECT_THROW(gr.premix(g, noDepth), Error);
  GuideRaySamples small = s;
  small.offsets[0] = Image(3, 4, 2);
  EXPECT_THROW(gr.premix(g, small), Error);
  GuideRaySamples outside = s;
  outside.offsets[0].at(2, 1, 1) = 0.75f;
  EXPECT_THROW(gr.premix(g, outside), Error);
  outside.offsets[0].at(2, 1, 1) = NAN;
  EXPECT_THROW(gr.premix(g, outside), Error);
  // A lobe the guides carry but a sample does not (or the other way round) would leave the
  // mixed colour different from the sum of its unmixed lobes.
  Frame withLobe = g;
  withLobe[Buffer::Diffuse] = Image(4, 4, 3, 1.0f);
  EXPECT_THROW(gr.premix(withLobe, s), Error);
  GuideRaySamples sampleLobe = s;
  sampleLobe.samples[0][Buffer::Diffuse] = Image(4, 4, 3, 1.0f);
  EXPECT_THROW(gr.premix(g, sampleLobe), Error);
  sampleLobe.samples[0][Buffer::Diffuse] = Image(4, 4, 3, 1.0f);
  EXPECT_NO_THROW(gr.premix(withLobe, sampleLobe));
  gr.premix(g, s);
  EXPECT_THROW(gr.resolve(Image(4, 3, 3)), Error);
}

}  // namespace
}  // namespace rtd
