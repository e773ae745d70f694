// RAE on the CPU (oneDNN): the library against the PyTorch model on the committed fixtures
// (python/rtdenoise_train/fixture.py: random weights, 21x13 frames, three frames with the
// hidden state carried, two input sets), the recurrence (identical inputs give different
// outputs; reset(), a camera cut and recurrent = false give the first-frame output), any
// input size, sanitized bad input, and weights-file errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "backend/cpu/cpu_denoiser.h"
#include "methods/rae/rae_codec_kernels.h"
#include "methods/rae/rae_fixture.h"
#include "methods/rae/rae_model.h"
#include "rtd/rtd.h"
#include "support/cpu_paths.h"
#include "support/test_frames.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

using test::loadRaeFixture;
using test::RaeFixture;

double maxAbsDifference(const Image& a, const Image& b) {
  double m = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) m = std::max(m, double(std::abs(a.pixels[i] - b.pixels[i])));
  return m;
}

// Float32 oneDNN against float64 PyTorch, through 13 convolutions and three frames of state:
// max |a - e| / (1 + |e|) < 1e-4 (the float32 rounding of ~100-term sums, compounded).
TEST(Rae, CpuMatchesPyTorchOverThreeFrames) {
  for (const char* inputs : {"color_albedo_normal", "color"}) {
    const RaeFixture f = loadRaeFixture(inputs);
    auto device = Device::create();
    auto d = device->createDenoiser("rae");
    d->set("weights", f.weights);
    for (size_t t = 0; t < f.frames.size(); ++t)
      EXPECT_LT(test::maxRelativeError(test::denoised(*d, f.frames[t]), f.expected[t]), 1e-4) << inputs << ", frame " << t;
  }
}

// Checklist 27: with the recurrence, the hidden state changes the output for identical frame
// inputs (fixture frames 1 and 2 are the same), in PyTorch and in the library; reset(), a
// camera cut and recurrent = false each give the first-frame output again.
TEST(Rae, HiddenStateChangesTheOutputAndResetClearsIt) {
  const RaeFixture f = loadRaeFixture("color_albedo_normal");
  EXPECT_GT(maxAbsDifference(f.expected[1], f.expected[2]), 1e-3) << "the fixture's frames 1 and 2 agree in PyTorch";
  auto device = Device::create();
  auto d = device->createDenoiser("rae");
  d->set("weights", f.weights);
  const Image first = test::denoised(*d, f.frames[1]);  // frame 1's input as a first frame
  const Image second = test::denoised(*d, f.frames[1]);
  EXPECT_GT(maxAbsDifference(first, second), 1e-3) << "identical inputs, different hidden states";
  d->reset();
  EXPECT_EQ(maxAbsDifference(test::denoised(*d, f.frames[1]), first), 0.0) << "after reset()";
  FrameInputs cut = f.frames[1].inputs();
  cut.cameraCut = true;
  Image out(f.frames[1].width, f.frames[1].height, 3);
  d->denoise(cut, out.view());
  EXPECT_EQ(maxAbsDifference(out, first), 0.0) << "on a camera cut";
  d->set("recurrent", "false");
  test::denoised(*d, f.frames[0]);
  EXPECT_EQ(maxAbsDifference(test::denoised(*d, f.frames[1]), first), 0.0) << "recurrent = false";
}

// Checklist 27: any input size, including sizes below and between multiples of 2^(L-1) = 8
// (1x1; 9x16: a multiple in y only; 33x17)
// (the built-in weights have 4 levels): finite, non-negative radiance of the frame's size.
TEST(Rae, AnyInputSize) {
  auto device = Device::create();
  auto d = device->createDenoiser("rae");
  for (auto [w, h] : {std::pair{1, 1}, {9, 16}, {33, 17}}) {
    synthetic::Scene scene;
    scene.width = w;
    scene.height = h;
    const Frame f = synthetic::makeFrame(scene, 0);
    const Image out = test::denoised(*d, f);
    ASSERT_EQ(out.width, w);
    ASSERT_EQ(out.height, h);
    EXPECT_TRUE(test::allFinite(out)) << w << "x" << h;
    for (float v : out.pixels) ASSERT_GE(v, 0.0f) << w << "x" << h;
  }
}

// The bad-input classes import sanitizes (NaN, +-Inf, huge values in colour, albedo and normal)
// reach neither the output nor the hidden state.
TEST(Rae, BadInputReachesNeitherOutputNorHiddenState) {
  synthetic::Scene scene;
  scene.width = 24;
  scene.height = 16;
  Frame f = synthetic::makeFrame(scene, 0);
  const float bad[] = {std::nanf(""), INFINITY, -INFINITY, 1e30f, -1e30f};
  int k = 0;
  for (Buffer b : {Buffer::Color, Buffer::Albedo, Buffer::Normal})
    for (size_t i = 7; i < f[b].pixels.size(); i += 37) f[b].pixels[i] = bad[k++ % 5];
  auto device = Device::create();
  auto d = device->createDenoiser("rae");
  for (int t = 0; t < 3; ++t) {
    const Image out = test::denoised(*d, f);
    ASSERT_TRUE(test::allFinite(out)) << "frame " << t;
  }
  auto* inspect = dynamic_cast<const PlaneInspection*>(d.get());
  ASSERT_NE(inspect, nullptr);
  size_t hidden = 0;
  inspect->forEachPlane([&](std::string_view name, const float* data, size_t count) {
    if (name != "hidden state") return;
    hidden += count;
    for (size_t i = 0; i < count; ++i) ASSERT_TRUE(std::isfinite(data[i])) << "hidden state value " << i;
  });
  EXPECT_GT(hidden, 0u);
}

// The encode/decode colour transform (rae_codec_simd.cpp: polynomial log1p and expm1 on
// vectors) against double precision on every CPU path: within 2 ulp (relative to the result;
// 0.85 and 0.97 measured)
// of log1p(max(c, 0) / k) (of the float quotient) and of expm1(clamp(y, 0, 12)) k, over values
// from 1e-30 to 1e30 (log1p) and -1 to 13 (expm1), 1003 of them (a tail after the vectors).
TEST(Rae, ColourTransformMatchesDoublePrecisionOnEveryCpuPath) {
  const int n = 1003;
  std::vector<float> c(n), k(n), y(n), out(n);
  for (int i = 0; i < n; ++i) {
    c[size_t(i)] = i % 7 == 0 ? (i % 2 ? 0.0f : -1.0f) : std::pow(10.0f, -30.0f + 60.0f * float(i) / n);
    k[size_t(i)] = 0.01f + float(i % 101) / 100.0f;
    y[size_t(i)] = -1.0f + 14.0f * float(i) / n;
  }
  const double ulp = std::ldexp(1.0, -23);
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath scoped(path);
    for (bool withK : {true, false}) {
      RTD_SIMD(raeLog1pRatio)(c.data(), withK ? k.data() : nullptr, out.data(), n);
      for (int i = 0; i < n; ++i) {
        const float q = std::max(c[size_t(i)], 0.0f) / (withK ? k[size_t(i)] : 1.0f);
        const double e = std::log1p(double(q));
        ASSERT_LE(std::abs(out[size_t(i)] - e), 2 * ulp * e) << cpuPathName(path) << ": log1p(" << q << ")";
      }
      RTD_SIMD(raeExpm1Scaled)(y.data(), withK ? k.data() : nullptr, out.data(), n, 12.0f);
      for (int i = 0; i < n; ++i) {
        const double e = std::expm1(std::clamp(double(y[size_t(i)]), 0.0, 12.0)) * (withK ? k[size_t(i)] : 1.0);
        ASSERT_LE(std::abs(out[size_t(i)] - e), 2 * ulp * e) << cpuPathName(path) << ": expm1(" << y[size_t(i)] << ")";
      }
    }
  }
}

// --threads bounds oneDNN's OpenMP threads (Debian's oneDNN runs on libgomp, not on the
// denoiser's oneTBB arena): a one-thread device starts no thread of its own, OpenMP's included.
// (ctest runs each test in a process of its own, where a second OpenMP thread would show; in a
// process whose earlier tests already started OpenMP's pool the count cannot grow either.)
TEST(Rae, OneThreadDeviceStartsNoOpenMpThread) {
  auto threads = [] {
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/task")) ++n;
    return n;
  };
  if (!std::filesystem::exists("/proc/self/task")) GTEST_SKIP() << "no /proc/self/task";
  const size_t before = threads();
  auto d = Device::create({.threads = 1})->createDenoiser("rae");
  synthetic::Scene scene;
  scene.width = 64;
  scene.height = 48;
  for (int t = 0; t < 2; ++t) test::denoised(*d, synthetic::makeFrame(scene, t));
  EXPECT_LE(threads(), before);
}

// A missing required buffer is named; the built-in weights' architecture is the documented one.
TEST(Rae, MissingAlbedoIsNamedAndBuiltinWeightsAreTheDocumentedModel) {
  auto device = Device::create();
  auto d = device->createDenoiser("rae");
  Frame f = test::flatFrame(8, 8, 0.5f);  // colour and normal, no albedo
  Image out(8, 8, 3);
  try {
    d->denoise(f.inputs(), out.view());
    FAIL() << "a frame without albedo was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("albedo"), std::string::npos) << e.what();
  }
  const rae::Weights w = rae::loadWeights("");
  EXPECT_EQ(w.source, "built-in");
  EXPECT_EQ(w.channels, (std::vector<int>{12, 16, 24, 32}));
  EXPECT_TRUE(w.albedo && w.normal);
  EXPECT_EQ(w.parameters(), 80831u);  // RAE().parameter_count() in PyTorch
}

// Bad weights files name the file and the field; the denoiser keeps the weights it had.
TEST(Rae, BadWeightsFileIsReportedAndTheOldWeightsStay) {
  const std::string dir = ::testing::TempDir();
  const std::string text = rae::builtinWeightsJson();
  auto write = [&](const std::string& name, std::string body) {
    std::ofstream(dir + "/" + name) << body;
    return dir + "/" + name;
  };
  std::string v2 = text;
  v2.replace(v2.find("\"version\": 1"), 12, "\"version\": 2");
  std::string shape = text;
  shape.replace(shape.find("\"shape\": ["), 10, "\"shape\": [1, ");
  std::string missing = text;
  missing.replace(missing.find("\"decB.0.bias\""), 13, "\"decB.0.bjas\"");
  for (auto [file, field] : {std::pair{write("rae_bad_version.json", v2), "'version'"},
                             {write("rae_bad_shape.json", shape), "shape"},
                             {write("rae_missing_tensor.json", missing), "'decB.0.bias' is missing"}}) {
    try {
      rae::loadWeights(file);
      ADD_FAILURE() << file << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(rae::loadWeights(dir + "/does_not_exist.json"), Error);

  auto device = Device::create();
  auto d = device->createDenoiser("rae");
  EXPECT_THROW(d->set("weights", dir + "/rae_bad_version.json"), Error);
  for (const auto& s : d->settings()) {
    if (s.name == "weights") {
      EXPECT_EQ(s.value, "") << "the setting still names the built-in weights";
    }
  }
  Frame g = test::flatFrame(8, 8, 0.5f);
  g[Buffer::Albedo] = Image(8, 8, 3, 0.5f);
  Image out(8, 8, 3);
  d->denoise(g.inputs(), out.view());
  EXPECT_TRUE(test::allFinite(out));
}

}  // namespace
}  // namespace rtd
