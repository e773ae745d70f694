// TNND on the CPU: the perception's shape and kernels on an analytic ramp, the parameter count,
// the row-wise step against the per-pixel definition, the agreement with the PyTorch model
// (fixture computed by python/rtdenoise_train/fixture.py), finite output for 1..K iterations,
// stable quality across the trained iteration range, and weights-file errors.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "methods/tnnd/tnnd_fixture.h"
#include "methods/tnnd/tnnd_model.h"
#include "rtd/rtd.h"
#include "support/test_frames.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

using tnnd::kPerception;
using tnnd::kState;

tnnd::State rampState(int w, int h) {
  // s_c(x, y) = a_c x + b_c y + d_c with different slopes per channel.
  tnnd::State s;
  tnnd::resize(s, w, h);
  for (int c = 0; c < kState; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) s[c](x, y) = 0.1f * float(c + 1) * x - 0.05f * float(c) * y + float(c);
  return s;
}

// Checklist 30: 39 values per pixel; on a linear ramp (interior pixels) Sobel x/y give the
// slopes, the Laplace is 0 and the Gaussian reproduces the value.
TEST(Tnnd, PerceptionOfARampHasTheSlopesAndZeroLaplace) {
  const tnnd::State s = rampState(9, 7);
  const std::array<float, kPerception> p = tnnd::perceive(s, 4, 3);
  static_assert(kPerception == 39 && std::tuple_size_v<std::array<float, kPerception>> == 39);
  for (int c = 0; c < kState; ++c) {
    const float value = s[c](4, 3);
    EXPECT_FLOAT_EQ(p[c], value);                                    // state
    if (c < 3) { EXPECT_NEAR(p[9 + c], value, 1e-5f); }                  // Gaussian of a ramp: the ramp
    EXPECT_NEAR(p[12 + c], 0.0f, 1e-5f) << "Laplace, channel " << c;  // Laplace of a ramp: 0
    EXPECT_NEAR(p[21 + c], 0.1f * float(c + 1), 1e-5f) << "Sobel x, channel " << c;
    EXPECT_NEAR(p[30 + c], -0.05f * float(c), 1e-5f) << "Sobel y, channel " << c;
  }
}

// Checklist 31: 39 x 9 rule weights + 9 biases = 360 (the thesis counts the 351 weights).
TEST(Tnnd, ParameterCountIs360) {
  EXPECT_EQ(tnnd::kParameters, 360);
  const tnnd::Weights w = tnnd::loadWeights("");
  EXPECT_EQ(w.w.size() + w.b.size(), 360u);
  EXPECT_EQ(w.source, "built-in");
}

// step() (row chunks, separable filters, Laplace as Gaussian - identity, fast sigmoid) equals
// the definition s + sigmoid(perceive(s) W) + b pixel by pixel, borders included.
TEST(Tnnd, StepIsPerceptionThenRule) {
  const int w = 70, h = 5;  // more than one 64-pixel chunk
  tnnd::State s = rampState(w, h), next;
  for (int c = 0; c < kState; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) s[c](x, y) += 0.3f * std::sin(float(x * 7 + y * 3 + c));
  tnnd::resize(next, w, h);
  const tnnd::Weights weights = tnnd::loadWeights(test::loadTnndFixture().weights);  // random, |W| ~ 0.4
  tnnd::step(weights, s, next);
  for (int y = 0; y < h; ++y)
    for (int x : {0, 1, 33, 63, 64, 65, 69}) {
      const auto p = tnnd::perceive(s, x, y);
      for (int j = 0; j < kState; ++j) {
        double z = 0;
        for (int k = 0; k < kPerception; ++k) z += double(p[k]) * weights.w[size_t(k) * kState + j];
        const double expected = s[j](x, y) + 1.0 / (1.0 + std::exp(-z)) + weights.b[j];
        EXPECT_NEAR(next[j](x, y), expected, 2e-5) << "pixel (" << x << ", " << y << ") channel " << j;
      }
    }
}

// The library against the PyTorch model (float64) on the committed fixture: random weights,
// HDR colour, rotated camera (world -> view normals), 5 iterations.
TEST(Tnnd, CpuMatchesPyTorch) {
  const test::TnndFixture f = test::loadTnndFixture();
  auto device = Device::create();
  auto d = device->createDenoiser("tnnd");
  d->set("weights", f.weights);
  d->set("iterations", std::to_string(f.iterations));
  Image out(f.frame.width, f.frame.height, 3);
  d->denoise(f.frame.inputs(), out.view());
  EXPECT_LT(test::maxRelativeError(out, f.expected), 2e-4);
}

// Checklist 31: finite output after every iteration count 1..48 (twice the trained maximum).
TEST(Tnnd, OutputIsFiniteAfter1ToKIterations) {
  synthetic::Scene scene;
  scene.width = 48;
  scene.height = 32;
  const Frame f = synthetic::makeFrame(scene, 0);
  auto device = Device::create();
  auto d = device->createDenoiser("tnnd");
  for (int k = 1; k <= 48; ++k) {
    d->set("iterations", std::to_string(k));
    Image out(f.width, f.height, 3);
    d->denoise(f.inputs(), out.view());
    ASSERT_TRUE(test::allFinite(out)) << k << " iterations";
    for (float v : out.pixels) ASSERT_GE(v, 0.0f) << k << " iterations";
  }
}

// Bad weights files name the file and the field; the denoiser keeps the weights it had.
TEST(Tnnd, BadWeightsFileIsReportedAndTheOldWeightsStay) {
  const std::string dir = ::testing::TempDir();
  const std::string bad = dir + "/tnnd_bad_version.json";
  std::string text = tnnd::builtinWeightsJson();
  text.replace(text.find("\"version\": 1"), 12, "\"version\": 2");
  std::ofstream(bad) << text;
  try {
    tnnd::loadWeights(bad);
    FAIL() << "version 2 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tnnd_bad_version.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'version'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tnnd::parseWeights(R"({"format": "rtdenoise-tnnd-weights", "version": 1, "colorTransform": "log1p",
                                      "normalSpace": "view", "W": [[1]], "b": []})", "short"), Error);
  EXPECT_THROW(tnnd::loadWeights(dir + "/does_not_exist.json"), Error);

  auto device = Device::create();
  auto d = device->createDenoiser("tnnd");
  EXPECT_THROW(d->set("weights", bad), Error);
  for (const auto& s : d->settings())
    if (s.name == "weights") { EXPECT_EQ(s.value, "") << "the setting still names the built-in weights"; }
  const Frame f = test::flatFrame(8, 8, 0.5f);
  Frame g = f;
  g[Buffer::Albedo] = Image(8, 8, 3, 0.5f);
  Image out(8, 8, 3);
  d->denoise(g.inputs(), out.view());
  EXPECT_TRUE(test::allFinite(out));
}

}  // namespace
}  // namespace rtd
