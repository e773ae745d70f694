// BMFR through the public API: exact reproduction of feature-linear images, the block grid,
// the two accumulation schedules, rank deficiency, and end to end on the synthetic scene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include "methods/bmfr/blocks.h"
#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

std::unique_ptr<Denoiser> makeBmfr(const BmfrSettings& s) {
  static auto device = Device::create();
  auto d = device->createDenoiser("bmfr");
  d->setSettings(s);
  return d;
}

// Illumination that is exactly a combination of [1, n, w, w^2] (non-negative on the scene).
float linearIllumination(const Frame& f, int x, int y) {
  const float* n = f[Buffer::Normal].pixel(x, y);
  const float* w = f[Buffer::Position].pixel(x, y);
  return 0.6f + 0.3f * n[1] + 0.2f * n[2] + 0.05f * w[0] - 0.04f * w[2] + 0.01f * w[0] * w[0] + 0.02f * w[1] * w[1];
}

// The synthetic frame with its colour replaced by albedo * linearIllumination (albedo 0, the
// sky, counts as 1 as in the demodulation).
Frame linearFrame(const synthetic::Scene& scene, int index) {
  Frame f = synthetic::makeFrame(scene, index);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float a = f[Buffer::Albedo].at(x, y, c);
        f[Buffer::Color].at(x, y, c) = linearIllumination(f, x, y) * (a > 1e-3f ? a : 1.0f);
      }
  return f;
}

double relativeRmse(const Image& a, const Image& b) {
  double err = 0, norm = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.at(x, y, c)) - b.at(x, y, c);
        err += d * d;
        norm += double(b.at(x, y, c)) * b.at(x, y, c);
      }
  return std::sqrt(err / norm);
}

bool allFinite(const Image& img) {
  for (float v : img.pixels)
    if (!std::isfinite(v)) return false;
  return true;
}

synthetic::Scene smallScene(int w, int h, float speed, float noise) {
  synthetic::Scene s;
  s.width = w;
  s.height = h;
  s.cameraSpeed = speed;
  s.noise = noise;
  return s;
}

TEST(Bmfr, DefaultsAreThePapers) {
  const BmfrSettings s;
  EXPECT_EQ(s.alphaNoisy, 0.2f);
  EXPECT_EQ(s.alphaFiltered, 0.1f);
  EXPECT_EQ(s.maxHistoryLength, 255);
  EXPECT_EQ(s.blockSize, BmfrBlockSize::Block32);
  EXPECT_EQ(s.noiseAmount, 0.01f);
  EXPECT_TRUE(s.featureNormal && s.featurePosition && s.featurePositionSquared);
  EXPECT_FALSE(s.featureMaterialId || s.featureRoughness);
  EXPECT_EQ(s.taa.taaAlpha, 0.2f);
  EXPECT_EQ(s.taa.taaNeighbourhood, TaaNeighbourhood::boxCross);  // [CODE] box + cross bounds
  EXPECT_EQ(s.taa.taaDomain, TaaDomain::display);                 // [CODE] TAA on display values
  // The authors' absolute 0.04 (Sponza) made scale-free: 4 pixel footprints (issue 12).
  EXPECT_FLOAT_EQ(s.reprojection.positionTolerance, 0.0f);
  EXPECT_FLOAT_EQ(s.reprojection.positionFootprints, 4.0f);
  EXPECT_FLOAT_EQ(s.reprojection.normalTolerance, 0.875f);  // |dn|^2 < 0.25
  const auto methods = listMethods();
  bool found = false;
  for (const auto& m : methods) found = found || (m.name == "bmfr" && m.cpu);
  EXPECT_TRUE(found);
}

// Frame 0 has no history: the output is the remodulated fit of the input itself.
double firstFrameError(BmfrSettings s, int w, int h) {
  const auto scene = smallScene(w, h, 0.0f, 0.0f);
  const Frame f = linearFrame(scene, 0);
  auto d = makeBmfr(s);
  Image out(w, h, 3);
  d->denoise(f.inputs(), out.view());
  EXPECT_TRUE(allFinite(out));
  return relativeRmse(out, f[Buffer::Color]);
}

TEST(Bmfr, LinearCombinationOfFeaturesIsReproducedExactlyWithoutRegularization) {
  BmfrSettings s;
  s.noiseAmount = 0.0f;
  EXPECT_LT(firstFrameError(s, 160, 96), 1e-5);
  s.blockSize = BmfrBlockSize::Block64;
  EXPECT_LT(firstFrameError(s, 160, 96), 1e-5);
}

TEST(Bmfr, LinearCombinationOfFeaturesIsReproducedWithinTheRegularizationTolerance) {
  BmfrSettings s;  // eps = 0.01 biases the weights slightly: measured 8.4e-5 here
  const double err = firstFrameError(s, 160, 96);
  std::printf("relative RMSE with eps = 0.01: %.3g\n", err);
  EXPECT_LT(err, 5e-4);
  EXPECT_GT(err, 1e-6);  // the regularization is really there
}

// Declared here, defined with the flat-wall test below.
Frame flatWallFrame(int w, int h);

TEST(Bmfr, SubsampledBlocksReproduceALinearCombination) {
  BmfrSettings s;
  s.noiseAmount = 0.0f;
  s.blockSize = BmfrBlockSize::Block64;
  s.samplesPerBlock = 36;  // Higginson's setting
  // Where the samples span every block's features (a wall), the fit is exact.
  const Frame wall = flatWallFrame(160, 96);
  auto d = makeBmfr(s);
  Image out(160, 96, 3);
  d->denoise(wall.inputs(), out.view());
  EXPECT_LT(relativeRmse(out, wall[Buffer::Color]), 1e-5);
  // On the scene, 36 samples can miss a thin object in a block, whose pixels are then
  // extrapolated: close, not exact (measured 1.7e-3).
  EXPECT_LT(firstFrameError(s, 160, 96), 5e-3);
}

TEST(Bmfr, MaterialIdFeatureIsUsedWhenEnabled) {
  // Illumination with a per-material step that no geometric feature explains.
  const auto scene = smallScene(160, 96, 0.0f, 0.0f);
  Frame f = linearFrame(scene, 0);
  f[Buffer::MaterialId] = f[Buffer::ObjectId];
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float a = f[Buffer::Albedo].at(x, y, c);
        f[Buffer::Color].at(x, y, c) += 0.3f * f[Buffer::MaterialId].at(x, y) * (a > 1e-3f ? a : 1.0f);
      }
  auto error = [&](bool useMaterial) {
    BmfrSettings s;
    s.noiseAmount = 0.0f;
    s.featureMaterialId = useMaterial;
    auto d = makeBmfr(s);
    Image out(f.width, f.height, 3);
    d->denoise(f.inputs(), out.view());
    return relativeRmse(out, f[Buffer::Color]);
  };
  const double with = error(true), without = error(false);
  EXPECT_LT(with, 1e-5);
  EXPECT_GT(without, 10 * with);
}

TEST(BmfrBlocks, EveryPixelInExactlyOneBlockEveryFrame) {
  for (int size : {32, 64})
    for (int frame = 0; frame < 16; ++frame) {
      const int w = 150, h = 77;
      const bmfr::BlockGrid g = bmfr::makeBlockGrid(w, h, size, frame, true);
      std::vector<int> count(size_t(w) * h, 0);
      for (int by = 0; by < g.blocksY; ++by)
        for (int bx = 0; bx < g.blocksX; ++bx)
          for (int y = g.y0(by); y < g.y0(by) + size; ++y)
            for (int x = g.x0(bx); x < g.x0(bx) + size; ++x)
              if (x >= 0 && y >= 0 && x < w && y < h) {
                ++count[size_t(y) * w + x];
                EXPECT_EQ(g.blockOf(x, y), by * g.blocksX + bx);
                EXPECT_TRUE(g.inImage(bx, by));
              }
      for (int c : count) ASSERT_EQ(c, 1) << "size " << size << " frame " << frame;
    }
}

TEST(BmfrBlocks, OffsetsRepeatEvery16Frames) {
  std::set<std::pair<int, int>> origins;
  for (int frame = 0; frame < 16; ++frame) {
    const auto g = bmfr::makeBlockGrid(1280, 720, 32, frame, true);
    const auto g16 = bmfr::makeBlockGrid(1280, 720, 32, frame + 16, true);
    EXPECT_EQ(g.originX, g16.originX);
    EXPECT_EQ(g.originY, g16.originY);
    EXPECT_GE(g.originX, -32);
    EXPECT_LE(g.originX, -1);
    origins.insert({g.originX, g.originY});
  }
  EXPECT_EQ(origins.size(), 16u);  // 16 distinct displacements, both axes
}

// The CPU method runs phase I, the fit and phase III band by band: each image row must be in
// exactly one band, and every row a block reads (mirrored rows included) in the block's band.
TEST(BmfrBlocks, RowBandsHoldEveryRowTheirBlocksRead) {
  for (int size : {32, 64})
    for (int h : {1, 5, 17, 31, 33, 64, 77, 100, 720})
      for (int frame = 0; frame < 16; ++frame) {
        const bmfr::BlockGrid g = bmfr::makeBlockGrid(40, h, size, frame, true);
        const std::vector<bmfr::RowBand> bands = bmfr::rowBands(g);
        std::vector<int> rowCount(size_t(h), 0);
        int blockRows = 0;
        for (const auto& b : bands) {
          for (int y = b.rowBegin; y < b.rowEnd; ++y) ++rowCount[size_t(y)];
          for (int by = b.blockRowBegin; by < b.blockRowEnd; ++by, ++blockRows)
            for (int y = g.y0(by); y < g.y0(by) + size; ++y) {
              const int read = bmfr::mirror(y, h);
              ASSERT_TRUE(read >= b.rowBegin && read < b.rowEnd)
                  << "size " << size << " height " << h << " frame " << frame << " block row " << by << " row " << y;
            }
        }
        for (int c : rowCount) ASSERT_EQ(c, 1) << "size " << size << " height " << h << " frame " << frame;
        int inImage = 0;
        for (int by = 0; by < g.blocksY; ++by) inImage += g.inImage(0, by) || g.inImage(1, by);
        EXPECT_EQ(blockRows, inImage);
        // Bands are short enough to stay in cache: at most two block rows each except in
        // images of fewer than two block rows.
        if (h >= 2 * size) {
          for (const auto& b : bands) EXPECT_LE(b.blockRowEnd - b.blockRowBegin, 2);
        }
      }
}

TEST(BmfrBlocks, BordersMirror) {
  EXPECT_EQ(bmfr::mirror(-1, 10), 0);
  EXPECT_EQ(bmfr::mirror(-2, 10), 1);
  EXPECT_EQ(bmfr::mirror(-10, 10), 9);
  EXPECT_EQ(bmfr::mirror(10, 10), 9);
  EXPECT_EQ(bmfr::mirror(11, 10), 8);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(bmfr::mirror(i, 10), i);
}

// A static camera and spatially uniform inputs whose value changes every frame: every pixel
// keeps its full history, so the outputs follow the two recursions exactly.
class BmfrSchedule : public ::testing::Test {
 protected:
  static constexpr int kFrames = 14;
  static float input(int t) { return 1.0f + float((t * 7) % 5); }  // 1, 3, 5, 2, 4, 1, ...
  std::vector<float> run(BmfrSettings s) {
    s.demodulate = false;
    s.taa.taa = false;
    const auto scene = smallScene(64, 48, 0.0f, 0.0f);
    auto d = makeBmfr(s);
    Frame f = synthetic::makeFrame(scene, 0);
    Image out(64, 48, 3);
    std::vector<float> values;
    for (int t = 0; t < kFrames; ++t) {
      for (auto& v : f[Buffer::Color].pixels) v = input(t);
      d->denoise(f.inputs(), out.view());
      double mean = 0, spread = 0;
      for (float v : out.pixels) mean += v;
      mean /= double(out.pixels.size());
      for (float v : out.pixels) spread = std::max(spread, std::abs(v - mean));
      EXPECT_LT(spread, 1e-4 * mean) << "frame " << t;  // still uniform
      values.push_back(float(mean));
    }
    return values;
  }
};

TEST_F(BmfrSchedule, PhaseOneIsACumulativeThenExponentialAverage) {
  BmfrSettings s;
  s.fit = false;
  s.accumulateFiltered = false;
  const auto out = run(s);
  double expected = 0, sum = 0;
  for (int t = 0; t < kFrames; ++t) {
    sum += input(t);
    const double w = std::max(1.0 / (t + 1), 0.2);
    expected = w * input(t) + (1 - w) * expected;
    if (t < 5) {  // the cumulative part is the mean
      EXPECT_NEAR(expected, sum / (t + 1), 1e-9);
    }
    EXPECT_NEAR(out[t], expected, 1e-5 * expected) << "frame " << t;
  }
}

TEST_F(BmfrSchedule, PhaseThreeUsesTenPercentWithThePhaseOneCount) {
  const auto out = run(BmfrSettings{});  // fit on: a uniform image is fitted exactly
  double a = 0, b = 0;
  for (int t = 0; t < kFrames; ++t) {
    const double n = t + 1;
    const double w1 = std::max(1.0 / n, 0.2), w2 = std::max(1.0 / n, 0.1);
    a = w1 * input(t) + (1 - w1) * a;
    b = w2 * a + (1 - w2) * b;
    EXPECT_NEAR(out[t], b, 1e-4 * b) << "frame " << t;
  }
}

// A flat wall facing the camera: constant normal and depth make n and w_z (and their
// squares) constant on every block, i.e. a rank-deficient T.
Frame flatWallFrame(int w, int h) {
  Frame f;
  f.width = w;
  f.height = h;
  for (Buffer b : {Buffer::Color, Buffer::Albedo, Buffer::Normal, Buffer::Position})
    f[b] = Image(w, h, bufferChannelCount(b));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float wx = 0.01f * x, wy = 0.01f * y;
      f[Buffer::Normal].at(x, y, 2) = 1.0f;
      f[Buffer::Position].at(x, y, 0) = wx;
      f[Buffer::Position].at(x, y, 1) = wy;
      f[Buffer::Position].at(x, y, 2) = -4.0f;
      for (int c = 0; c < 3; ++c) {
        f[Buffer::Albedo].at(x, y, c) = 0.5f;
        f[Buffer::Color].at(x, y, c) = 0.5f * (0.2f + 0.3f * wx + 0.1f * wy * wy + 0.05f * c);
      }
    }
  return f;
}

TEST(Bmfr, FlatWallIsFiniteWithRegularization) {
  const Frame f = flatWallFrame(96, 64);
  for (float eps : {0.01f, 0.0f}) {  // eps = 0: zero columns, reported pivots, still finite
    BmfrSettings s;
    s.noiseAmount = eps;
    auto d = makeBmfr(s);
    Image out(96, 64, 3);
    for (int t = 0; t < 3; ++t) {
      d->denoise(f.inputs(), out.view());
      ASSERT_TRUE(allFinite(out)) << "eps " << eps;
    }
    EXPECT_LT(relativeRmse(out, f[Buffer::Color]), 2e-3) << "eps " << eps;
  }
}

// A position channel that is constant on a block up to rounding (a wall's z = -4 +- 1 ulp, a
// floor's y = 0 +- 1e-7 as a ray caster computes them) is not a feature: neither w nor its
// square (w - c)^2, whose ulp^2 values would otherwise be normalized into a [-1, 1] column of
// rounding noise that fits the colour noise and changes with the scene's scale (issue 12).
TEST(Bmfr, RoundingNoiseOfAConstantPositionIsNotAFeature) {
  const int w = 96, h = 64;
  Frame exact = flatWallFrame(w, h);
  for (int y = 0; y < h; ++y)  // noisy colour, for the spurious feature to fit
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) exact[Buffer::Color].at(x, y, c) *= 0.5f + float((x * 7 + y * 13 + c * 5) % 11) / 10.0f;
  for (float z : {-4.0f, 0.0f}) {
    Frame a = exact, b = exact;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int k = (x * 31 + y * 17) % 3 - 1;  // -1, 0, 1
        a[Buffer::Position].at(x, y, 2) = z;
        b[Buffer::Position].at(x, y, 2) = z == 0.0f ? 1e-7f * float(k) : k ? std::nextafter(z, float(k) * 8.0f) : z;
      }
    auto da = makeBmfr(BmfrSettings{}), db = makeBmfr(BmfrSettings{});
    Image outA(w, h, 3), outB(w, h, 3);
    double diff = 0, peak = 0;
    for (int t = 0; t < 3; ++t) {
      da->denoise(a.inputs(), outA.view());
      db->denoise(b.inputs(), outB.view());
      for (size_t i = 0; i < outA.pixels.size(); ++i) {
        diff = std::max(diff, std::abs(double(outA.pixels[i]) - outB.pixels[i]));
        peak = std::max(peak, double(outA.pixels[i]));
      }
    }
    EXPECT_LE(diff, 1e-6 * peak) << "z = " << z << " with rounding noise";
  }
}

TEST(Bmfr, DeterministicPerFrame) {
  // The regularization noise and block offsets depend only on the frame index since the
  // reset: two denoisers (and one after reset()) give bit-identical sequences.
  const auto scene = smallScene(96, 64, 0.02f, 1.0f);
  auto a = makeBmfr(BmfrSettings{}), b = makeBmfr(BmfrSettings{});
  Image outA(96, 64, 3), outB(96, 64, 3);
  std::vector<Image> first;
  for (int t = 0; t < 3; ++t) {
    const Frame f = synthetic::makeFrame(scene, t);
    a->denoise(f.inputs(), outA.view());
    b->denoise(f.inputs(), outB.view());
    EXPECT_EQ(outA.pixels, outB.pixels) << "frame " << t;
    first.push_back(outA);
  }
  a->reset();
  for (int t = 0; t < 3; ++t) {
    a->denoise(synthetic::makeFrame(scene, t).inputs(), outA.view());
    EXPECT_EQ(outA.pixels, first[size_t(t)].pixels) << "frame " << t << " after reset";
  }
}

TEST(Bmfr, ImagesSmallerThanABlockAreFinite) {
  for (auto size : {std::pair{5, 3}, std::pair{40, 17}}) {
    const Frame f = flatWallFrame(size.first, size.second);
    for (auto block : {BmfrBlockSize::Block32, BmfrBlockSize::Block64}) {
      BmfrSettings s;
      s.blockSize = block;
      auto d = makeBmfr(s);
      Image out(f.width, f.height, 3);
      for (int t = 0; t < 2; ++t) d->denoise(f.inputs(), out.view());
      EXPECT_TRUE(allFinite(out));
      EXPECT_LT(relativeRmse(out, f[Buffer::Color]), 1e-2);
    }
  }
}

// Mean RMSE to the reference of the input and the output over frames 12-19 of a moving camera.
std::pair<double, double> movingCameraErrors(BmfrSettings s) {
  const auto scene = smallScene(192, 112, 0.02f, 1.0f);
  // Scaled to the scene: a pixel here spans ~0.1 world units on the back wall, 7x the
  // footprint at 1280x720, so the 0.04 of the authors' Sponza becomes 0.3.
  s.reprojection.positionTolerance = 0.3f;
  auto d = makeBmfr(s);
  Image out(scene.width, scene.height, 3), reference;
  double inputError = 0, outputError = 0;
  for (int t = 0; t < 20; ++t) {
    const Frame f = synthetic::makeFrame(scene, t, &reference);
    d->denoise(f.inputs(), out.view());
    EXPECT_TRUE(allFinite(out)) << "frame " << t;
    if (t >= 12) {
      inputError += test::rmse(f[Buffer::Color], reference);
      outputError += test::rmse(out, reference);
    }
  }
  return {inputError / 8, outputError / 8};
}

TEST(Bmfr, EndToEndOnAMovingCamera) {
  const auto [input, output] = movingCameraErrors(BmfrSettings{});
  std::printf("RMSE over frames 12-19: input %.4f, output %.4f\n", input, output);
  EXPECT_LT(output, 0.2 * input);
}

TEST(Bmfr, EndToEndWithSubsampledBlocks) {
  BmfrSettings s;
  s.blockSize = BmfrBlockSize::Block64;
  s.samplesPerBlock = 36;  // Higginson's setting
  const auto [input, output] = movingCameraErrors(s);
  std::printf("RMSE over frames 12-19, 64x64 blocks, 36 samples: input %.4f, output %.4f\n", input, output);
  EXPECT_LT(output, 0.2 * input);
}

// Gradient energy of the error along the last frame's block edges against everywhere else.
double blockEdgeRatio(const Image& out, const Image& ref, const bmfr::BlockGrid& g) {
  auto err = [&](int x, int y) {
    double e = 0;
    for (int c = 0; c < 3; ++c) e += double(out.at(x, y, c)) - ref.at(x, y, c);
    return e;
  };
  double edge = 0, other = 0;
  int nEdge = 0, nOther = 0;
  for (int y = 1; y < out.height; ++y)
    for (int x = 1; x < out.width; ++x) {
      const double gx = std::abs(err(x, y) - err(x - 1, y)), gy = std::abs(err(x, y) - err(x, y - 1));
      const bool edgeX = (x - g.originX) % g.size == 0, edgeY = (y - g.originY) % g.size == 0;
      (edgeX ? edge : other) += gx;
      (edgeX ? nEdge : nOther) += 1;
      (edgeY ? edge : other) += gy;
      (edgeY ? nEdge : nOther) += 1;
    }
  return (edge / nEdge) / (other / nOther);
}

double staticSceneBlockRatio(const BmfrSettings& s, int frames) {
  const auto scene = smallScene(192, 128, 0.0f, 1.0f);
  auto d = makeBmfr(s);
  Image out(scene.width, scene.height, 3), reference;
  for (int t = 0; t < frames; ++t) {
    synthetic::Scene sc = scene;
    sc.seed = uint32_t(t + 1);  // a new noise realization every frame
    const Frame f = synthetic::makeFrame(sc, 0, &reference);
    d->denoise(f.inputs(), out.view());
  }
  const bmfr::BlockGrid g = bmfr::makeBlockGrid(scene.width, scene.height, 32, frames - 1, s.blockOffsets);
  return blockEdgeRatio(out, reference, g);
}

TEST(Bmfr, NoBlockPatternOnAStaticSceneAfter16Frames) {
  const double ratio = staticSceneBlockRatio(BmfrSettings{}, 20);
  std::printf("block-edge gradient ratio: %.3f\n", ratio);
  EXPECT_LT(ratio, 1.3);
  // The measure does see blocks: one fixed grid with no phase III accumulation and no TAA.
  BmfrSettings fixed;
  fixed.blockOffsets = false;
  fixed.accumulateFiltered = false;
  fixed.taa.taa = false;
  const double fixedRatio = staticSceneBlockRatio(fixed, 20);
  std::printf("block-edge gradient ratio, fixed grid, no phase III/TAA: %.3f\n", fixedRatio);
  EXPECT_GT(fixedRatio, 1.5 * ratio);
}

}  // namespace
}  // namespace rtd


#ifdef HAVE_RTDENOISE_RENDER
#include "rtd/render/render.h"
#include "support/test_frames.h"

namespace rtd {
namespace {

// End to end on the path tracer's "pillars" scene (sun and sky, moving camera, 1 spp, full
// global illumination): the last frame's output against a 128-spp reference.
TEST(Bmfr, EndToEndOnAPathTracedSequence) {
  render::RenderSettings rs;
  rs.width = 128;
  rs.height = 72;
  render::Renderer renderer(render::Scene::load("pillars"), rs);
  BmfrSettings s;
  // Scaled to the scene: at 128x72 a pixel spans ~0.1 world units on the pillars and much more
  // on the grazing floor.
  s.reprojection.positionTolerance = 0.3f;
  auto d = makeBmfr(s);
  Image out(rs.width, rs.height, 3);
  constexpr int kFrames = 12;
  Frame f;
  for (int t = 0; t < kFrames; ++t) {
    f = renderer.render(t);
    d->denoise(f.inputs(), out.view());
    ASSERT_TRUE(allFinite(out)) << "frame " << t;
  }
  const Image reference = renderer.renderReference(kFrames - 1, 128);
  const double input = test::rmse(f[Buffer::Color], reference), output = test::rmse(out, reference);
  std::printf("pillars 128x72, frame %d: RMSE input %.4f, output %.4f\n", kFrames - 1, input, output);
  // Blocks of 32 pixels cover a quarter of this small image's height and only 12 frames are
  // accumulated, so the gain is smaller than at 720p (measured: about 2x).
  EXPECT_LT(output, 0.6 * input);
}

}  // namespace
}  // namespace rtd
#endif
