// Sequence evaluation: temporal error, warm-up split, directory matching and its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "rtd/eval/evaluate.h"
#include "rtd/sequence.h"

using namespace rtd;
using namespace rtd::eval;
namespace fs = std::filesystem;

namespace {
Image gradient(int w, int h, float shift) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.2f + 0.6f * float(x + shift) / float(w) + 0.05f * c;
  return img;
}

EvalSettings fast(int warmup = 0) {
  EvalSettings s;
  s.warmupFrames = warmup;
  s.computeFlip = s.computeHdrFlip = false;
  s.toneMap.op = ToneMapSettings::Operator::Clamp;
  return s;
}

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("rtd_eval_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST(TemporalError, FrozenIdenticalFramesAreZero) {
  SequenceEvaluator ev(fast());
  const Image img = gradient(16, 12, 0);
  for (int i = 0; i < 5; ++i) ev.add(i + 1, img, img);
  EXPECT_TRUE(std::isnan(ev.frames()[0].temporalError));  // no previous frame
  for (int i = 1; i < 5; ++i) {
    EXPECT_EQ(ev.frames()[i].temporalError, 0.0);
    EXPECT_EQ(ev.frames()[i].temporalErrorVsReference, 0.0);
    EXPECT_EQ(ev.frames()[i].referenceTemporalError, 0.0);
  }
  EXPECT_EQ(ev.steady().mean.temporalError, 0.0);
}

TEST(TemporalError, GrowsWithInjectedFlicker) {
  // Result = reference with alternating +-k brightness; with the clamp tone map and values far
  // from 0 and 1 the luma change is about 2k (times the sRGB slope) and grows with k.
  double last = 0, lastVs = 0;
  for (float k : {0.01f, 0.03f, 0.08f}) {
    SequenceEvaluator ev(fast());
    const Image ref(16, 12, 3, 0.2f);
    for (int t = 0; t < 6; ++t) {
      Image res = ref;
      for (float& v : res.pixels) v += (t % 2 ? k : -k);
      ev.add(t, res, ref);
    }
    const double e = ev.steady().mean.temporalError, vs = ev.steady().mean.temporalErrorVsReference;
    EXPECT_GT(e, last);
    EXPECT_GT(vs, lastVs);
    EXPECT_NEAR(e, vs, 1e-12);  // the reference is static, so both measures agree
    last = e;
    lastVs = vs;
  }
}

TEST(TemporalError, FreezingIsNotRewarded) {
  // A moving reference and a frozen result: raw temporal error 0, but the reference-relative
  // error equals the reference's own change.
  SequenceEvaluator ev(fast());
  const Image frozen = gradient(32, 8, 0);
  for (int t = 0; t < 4; ++t) ev.add(t, frozen, gradient(32, 8, float(t)));
  const auto& m = ev.frames()[3];
  EXPECT_EQ(m.temporalError, 0.0);
  EXPECT_GT(m.referenceTemporalError, 0.0);
  EXPECT_NEAR(m.temporalErrorVsReference, m.referenceTemporalError, 1e-9);
}

TEST(SequenceEval, WarmupFramesAreAveragedSeparately) {
  SequenceEvaluator ev(fast(2));
  const Image ref = gradient(16, 12, 0);
  Image bad = ref;
  for (float& v : bad.pixels) v *= 0.5f;
  ev.add(1, bad, ref);
  ev.add(2, bad, ref);
  for (int i = 3; i <= 6; ++i) ev.add(i, ref, ref);
  EXPECT_EQ(ev.warmup().frames, 2);
  EXPECT_EQ(ev.steady().frames, 4);
  EXPECT_TRUE(std::isinf(ev.steady().mean.psnr));
  EXPECT_LT(ev.warmup().mean.psnr, 20.0);
  EXPECT_TRUE(ev.frames()[0].warmup && ev.frames()[1].warmup && !ev.frames()[2].warmup);
}

TEST(SequenceEval, DirectoriesMatchByFrameNumber) {
  const fs::path ref = freshDir("match_ref"), res = freshDir("match_res");
  for (int n = 3; n <= 5; ++n) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", n);
    writeRgbExr(ref / name, gradient(12, 8, float(n)));
    writeRgbExr(res / name, gradient(12, 8, float(n)));
  }
  const auto streams = evaluateDirectories(ref, res, std::nullopt, fast());
  ASSERT_EQ(streams.size(), 1u);
  ASSERT_EQ(streams[0].frames.size(), 3u);
  EXPECT_EQ(streams[0].frames[0].number, 3);
  EXPECT_TRUE(std::isinf(streams[0].steady.mean.psnr));
  EXPECT_NE(metricsJson(streams, fast()).find("\"psnr\": \"inf\""), std::string::npos);
  fs::remove_all(ref);
  fs::remove_all(res);
}

TEST(SequenceEval, MissingAndMismatchedFramesNameTheFile) {
  const fs::path ref = freshDir("bad_ref"), res = freshDir("bad_res");
  writeRgbExr(ref / "frame_0001.exr", gradient(12, 8, 0));
  writeRgbExr(res / "frame_0001.exr", gradient(12, 8, 0));
  writeRgbExr(res / "frame_0002.exr", gradient(12, 8, 0));
  // Reference lacks frame 2.
  try {
    evaluateDirectories(ref, res, std::nullopt, fast());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame_0002.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("reference"), std::string::npos) << e.what();
  }
  // Size mismatch.
  writeRgbExr(ref / "frame_0002.exr", gradient(10, 8, 0));
  try {
    evaluateDirectories(ref, res, std::nullopt, fast());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame_0002.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("12x8"), std::string::npos) << e.what();
  }
  // A gap in the result's frames.
  writeRgbExr(ref / "frame_0002.exr", gradient(12, 8, 0));
  fs::remove(res / "frame_0002.exr");
  writeRgbExr(res / "frame_0003.exr", gradient(12, 8, 0));
  try {
    evaluateDirectories(ref, res, std::nullopt, fast());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 2 is missing"), std::string::npos) << e.what();
  }
  // A directory that does not exist.
  EXPECT_THROW(evaluateDirectories(ref / "nope", res, std::nullopt, fast()), Error);
  fs::remove_all(ref);
  fs::remove_all(res);
}

TEST(SequenceEval, NonFiniteResultValuesAreCountedAndPenalized) {
  SequenceEvaluator ev(fast());
  const Image ref = gradient(16, 12, 0);
  Image res = ref;
  res.at(3, 4, 1) = std::numeric_limits<float>::quiet_NaN();
  res.at(5, 6, 0) = std::numeric_limits<float>::infinity();
  const FrameMetrics& m = ev.add(1, res, ref);
  EXPECT_EQ(m.nonFiniteValues, 2u);
  EXPECT_TRUE(std::isfinite(m.psnr));
  EXPECT_GT(m.relMse, 0.0);
  EXPECT_EQ(ev.steady().mean.nonFiniteValues, 2u);
  EXPECT_NE(summaryTable({{"r", ev.frames(), ev.steady(), ev.warmup()}}, fast()).find("2 NaN/Inf"), std::string::npos);
}
