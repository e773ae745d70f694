// Temporal accumulation: convergence and variance on i.i.d. noise, exact moments for short
// histories, the CMA-to-EMA schedule, history reset on disocclusion, demodulation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "passes/temporal_accumulation.h"
#include "support/test_frames.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

TEST(Accumulation, NewSampleWeightIsCumulativeThenExponential) {
  // w = max(1/n, alpha): 1, 1/2, 1/3, 1/4, 1/5, then alpha (Koskela et al. 2019 Sec. 4.1).
  const float expected[] = {1.0f, 0.5f, 1.0f / 3, 0.25f, 0.2f, 0.2f, 0.2f};
  for (int n = 1; n <= 7; ++n) EXPECT_FLOAT_EQ(newSampleWeight(float(n), 0.2f), expected[n - 1]);
  EXPECT_FLOAT_EQ(newSampleWeight(12.0f, 0.1f), 0.1f);
  EXPECT_FLOAT_EQ(newSampleWeight(8.0f, 0.1f), 0.125f);
}

// Feeding x1..x4 at a static pixel: with alpha = 0.2 the first four weights are 1, 1/2, 1/3, 1/4,
// i.e. a true average, so the moments give the exact (population) variance of the samples.
TEST(Accumulation, MomentsGiveExactVarianceForShortHistories) {
  const float xs[] = {0.3f, 1.7f, 0.2f, 4.0f};
  const Frame f = test::flatFrame(3, 3, 0.0f);
  const FrameData d = test::toFrameData(f);
  Reprojection rp;
  TemporalAccumulator acc;
  acc.resize(3, 3);
  double sum = 0, sum2 = 0;
  for (int k = 0; k < 4; ++k) {
    reproject(d, k ? &d : nullptr, ReprojectionSettings{}, rp);
    Plane3 grey;
    resize(grey, 3, 3, xs[k]);  // grey: luminance == value
    acc.run(rp, grey, 0.2f, 0.2f, 255);
    sum += xs[k];
    sum2 += double(xs[k]) * xs[k];
    const double n = k + 1, mean = sum / n, var = sum2 / n - mean * mean;
    EXPECT_NEAR(acc.moment1()(1, 1), mean, 1e-5);
    EXPECT_NEAR(acc.moment2()(1, 1), sum2 / n, 1e-5);
    EXPECT_NEAR(acc.temporalVariance(4), var, 1e-4);
    EXPECT_NEAR(acc.color()[0](1, 1), mean, 1e-5);
    EXPECT_EQ(acc.historyLength()(1, 1), float(k + 1));
  }
}

// i.i.d. noise of mean mu and variance s2 on a static scene: the cumulative average has
// variance s2 / n; the exponential average (weight a) tends to s2 * a / (2 - a).
TEST(Accumulation, IidNoiseConvergesToTheMeanWithTheExpectedVariance) {
  const int w = 96, h = 96;
  const float mu = 0.5f, halfWidth = 0.5f;  // uniform on [0, 1]: variance 1/12
  const double s2 = 1.0 / 12.0;
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> u(mu - halfWidth, mu + halfWidth);

  auto run = [&](float alpha, int frames) {
    auto device = Device::create();
    AccumulateSettings s;
    s.alpha = alpha;
    s.maxHistoryLength = 65535;
    auto denoiser = device->createDenoiser(s);
    Frame f = test::flatFrame(w, h, 0.0f);
    Image out(w, h, 3);
    for (int k = 0; k < frames; ++k) {
      for (size_t i = 0; i < size_t(w) * h; ++i) {
        const float v = u(rng);
        for (int c = 0; c < 3; ++c) f[Buffer::Color].pixels[i * 3 + c] = v;
      }
      denoiser->denoise(f.inputs(), out.view());
    }
    double mean = 0, var = 0;
    for (size_t i = 0; i < size_t(w) * h; ++i) mean += out.pixels[i * 3];
    mean /= double(w) * h;
    for (size_t i = 0; i < size_t(w) * h; ++i) var += std::pow(out.pixels[i * 3] - mean, 2);
    var /= double(w) * h - 1;
    return std::pair{mean, var};
  };

  // Cumulative average over 20 frames (alpha below 1/20).
  auto [m1, v1] = run(0.01f, 20);
  EXPECT_NEAR(m1, mu, 4 * std::sqrt(s2 / 20 / (w * h)));
  EXPECT_NEAR(v1 / (s2 / 20), 1.0, 0.06);  // 9216 pixels: relative std of the estimate ~1.5%
  // Exponential average, well past the CMA phase.
  auto [m2, v2] = run(0.2f, 60);
  EXPECT_NEAR(m2, mu, 0.01);
  EXPECT_NEAR(v2 / (s2 * 0.2 / 1.8), 1.0, 0.06);
}

TEST(Accumulation, DisocclusionResetsHistoryAndNeighboursKeepIt) {
  const int w = 8, h = 4;
  auto device = Device::create();
  auto denoiser = device->createDenoiser("accumulate");
  Frame f = test::flatFrame(w, h, 1.0f);
  Image out(w, h, 3);
  for (int k = 0; k < 8; ++k) denoiser->denoise(f.inputs(), out.view());
  // A new object (id 2) on the left half, radiance 0 everywhere.
  Frame g = test::flatFrame(w, h, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w / 2; ++x) g[Buffer::ObjectId].at(x, y) = 2.0f;
  denoiser->denoise(g.inputs(), out.view());
  for (int y = 0; y < h; ++y) {
    EXPECT_EQ(out.at(0, y), 0.0f);                   // history reset: the new sample alone
    EXPECT_NEAR(out.at(w - 1, y), 0.8f, 1e-6);       // EMA: 0.2 * 0 + 0.8 * 1
  }
  // reset() forgets everything.
  denoiser->reset();
  denoiser->denoise(f.inputs(), out.view());
  EXPECT_EQ(out.at(w - 1, 0), 1.0f);
}

TEST(Accumulation, ConstantImageIsAFixedPointUnderCameraMotion) {
  synthetic::Scene scene;
  scene.width = 64;
  scene.height = 36;
  scene.noise = 0.0f;
  auto device = Device::create();
  auto denoiser = device->createDenoiser("accumulate");
  Image out(scene.width, scene.height, 3), ref;
  for (int k = 0; k < 5; ++k) {
    Frame f = synthetic::makeFrame(scene, k, &ref);
    denoiser->denoise(f.inputs(), out.view());
  }
  // Noise-free input: demodulation/remodulation is exact and textures do not smear beyond
  // the bilinear footprint at checker edges.
  double err = 0;
  for (size_t i = 0; i < out.pixels.size(); ++i) err += std::abs(out.pixels[i] - ref.pixels[i]);
  EXPECT_LT(err / out.pixels.size(), 0.01);
}

TEST(Accumulation, DemodulationIsSafeForZeroAlbedoAndInvertible) {
  const int w = 4, h = 2;
  Frame f = test::flatFrame(w, h, 0.6f);
  f[Buffer::Albedo] = Image(w, h, 3, 0.5f);
  f[Buffer::Albedo].at(0, 0, 0) = 0.0f;  // black albedo channel: must not divide by zero
  auto device = Device::create();
  auto denoiser = device->createDenoiser("accumulate");
  Image out(w, h, 3);
  denoiser->denoise(f.inputs(), out.view());
  EXPECT_TRUE(test::allFinite(out));
  for (float v : out.pixels) EXPECT_NEAR(v, 0.6f, 1e-6);  // remodulation undoes demodulation
}

TEST(Accumulation, ASizeChangeResizesAndResetsHistory) {
  auto denoiser = Device::create()->createDenoiser("accumulate");
  Image out(8, 4, 3);
  for (int k = 0; k < 4; ++k) denoiser->denoise(test::flatFrame(8, 4, 1.0f).inputs(), out.view());
  // Smaller frames: no stale history of the old size may be read.
  Image small(5, 3, 3);
  denoiser->denoise(test::flatFrame(5, 3, 0.25f).inputs(), small.view());
  for (float v : small.pixels) EXPECT_EQ(v, 0.25f);
  denoiser->denoise(test::flatFrame(5, 3, 0.75f).inputs(), small.view());
  for (float v : small.pixels) EXPECT_FLOAT_EQ(v, 0.5f);  // second sample: cumulative average
}

TEST(Accumulation, OutputIsWrittenIntoFloat4ViewsWithStrides) {
  Frame f = test::flatFrame(5, 3, 0.25f);
  Image out(5, 3, 4, -1.0f);
  auto denoiser = Device::create()->createDenoiser("accumulate");
  denoiser->denoise(f.inputs(), out.view());
  for (int i = 0; i < 15; ++i) {
    EXPECT_FLOAT_EQ(out.pixels[size_t(i) * 4 + 0], 0.25f);
    EXPECT_FLOAT_EQ(out.pixels[size_t(i) * 4 + 3], 1.0f);
  }
}

}  // namespace
}  // namespace rtd
