// Evaluation of reflections (src/eval/reflections.cpp): metrics on masked pixels against hand
// values, and the reflection motion vectors of a rendered mirror floor against the brute-force
// search (Voorhuis Sec. 7.4: more than 90% within one pixel).
#ifdef HAVE_RTDENOISE_EVAL
#include <gtest/gtest.h>

#include <cmath>
#include <unistd.h>

#include <filesystem>

#include "rtd/eval/metrics.h"
#include "rtd/eval/reflections.h"
#include "rtd/rtd.h"
#ifdef HAVE_RTDENOISE_RENDER
#include "rtd/render/render.h"
#endif

namespace rtd::eval {
namespace {

TEST(ReflectionEval, MaskedPsnrCountsOnlyMaskedPixels) {
  Image a(4, 2, 3, 0.5f), b(4, 2, 3, 0.5f), mask(4, 2, 1, 0.0f);
  for (int c = 0; c < 3; ++c) b.at(0, 0, c) = 0.6f;  // the only difference, outside the mask
  mask.at(1, 0) = mask.at(2, 1) = 1.0f;
  EXPECT_TRUE(std::isinf(maskedPsnr(a, b, mask)));
  mask.at(0, 0) = 1.0f;  // now inside: MSE = 3 * 0.01 / (3 pixels * 3 channels)
  EXPECT_NEAR(maskedPsnr(a, b, mask), 10.0 * std::log10(9.0 / 0.03), 1e-4);
  EXPECT_TRUE(std::isnan(maskedPsnr(a, b, Image(4, 2, 1, 0.0f))));  // no pixel: undefined
}

TEST(ReflectionEval, MaskedSsimIsTheMeanOfTheMapOverTheMask) {
  Image a(16, 16, 3), b(16, 16, 3), left(16, 16, 1, 0.0f);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) {
        a.at(x, y, c) = 0.3f + 0.02f * float((x * 7 + y * 3 + c) % 11);
        b.at(x, y, c) = x < 8 ? a.at(x, y, c) : 1.0f - a.at(x, y, c);  // right half differs
        if (x < 4) left.at(x, y) = 1.0f;
      }
  Image map;
  ssim(a, b, 1.0, &map);
  double sum = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 4; ++x) sum += map.at(x, y);
  EXPECT_NEAR(maskedSsim(a, b, left), sum / 64, 1e-9);
  EXPECT_GT(maskedSsim(a, b, left), 0.9);
}

#ifdef HAVE_RTDENOISE_RENDER
TEST(ReflectionEval, MirrorFloorMotionMatchesBruteForce) {
  // The built-in mirror floor under its sideways camera, 5 frames of 64x36.
  const auto dir = std::filesystem::temp_directory_path() / ("rtd_reflection_eval_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  {
    render::RenderSettings rs;
    rs.width = 64;
    rs.height = 36;
    render::Renderer r(render::Scene::load("mirrorfloor"), rs);
    SequenceWriter w(dir);
    for (int i = 10; i < 15; ++i) w.write(r.render(i));
    w.finish();
  }
  auto seq = SequenceReader::open(dir);
  const auto frames = reflectionMotionError(*seq);
  ASSERT_EQ(frames.size(), 4u);
  for (const auto& f : frames) {
    EXPECT_GT(f.pixels, 300u);
    EXPECT_GT(f.withinOnePixel, 0.9) << "frame " << f.number;  // the paper's level
    EXPECT_LT(f.meanError, 0.5) << "frame " << f.number;
    EXPECT_LT(f.meanTaps, 60) << "frame " << f.number;           // a few steps, not a window
  }
  // Both searches refined by Eqs. 2-3 instead of the quadratic fit (`--eq23-subpixel`): the same
  // pixels, as good a match, other subpixel positions.
  ReflectionMotionSettings eq23;
  eq23.subpixelFit = SvgfSubpixelFit::inverseDistance;
  const auto other = reflectionMotionError(*seq, eq23);
  ASSERT_EQ(other.size(), frames.size());
  bool differs = false;
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(other[i].pixels, frames[i].pixels);
    EXPECT_GT(other[i].withinOnePixel, 0.9);
    differs = differs || other[i].meanError != frames[i].meanError;
  }
  EXPECT_TRUE(differs) << "subpixelFit has no effect";
  std::filesystem::remove_all(dir);
}
#endif

}  // namespace
}  // namespace rtd::eval
#endif
