// Method "bmfr" on Vulkan against the CPU: pass by pass (the fit and synthesis on a first frame,
// phase III alone) and over short sequences with a moving camera, for the defaults and the
// non-default settings (64x64 blocks, samples per block, other feature sets), on 67x41 (smaller
// than two blocks, not a multiple of the 16x16 workgroup) and 100x70 (several blocks, borders
// mirrored on every side).
#if __has_include("rtd/methods/bmfr.h")
#include <cmath>
#include <cstdio>

#include "backend/vulkan/vulkan_denoiser.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// Tolerances, per frame and channel, relative to max|ref|: max abs error <= kBmfrMaxRel * max|ref|,
// mean abs error <= kBmfrMeanRel * max|ref|.
//
// The GPU fit sums its reductions (feature ranges, column norms, dot products) in another order
// than the CPU (a tree over 256 threads against the CPU's 8-wide vectors over 256-row tiles,
// followed by a QR of the stacked tile triangles), and a GPU's division and sqrt need not be
// correctly rounded; the fitted weights carry those rounding differences, amplified by the
// block matrix's condition number, which the regularization noise keeps moderate. Measured on
// lavapipe: max 3.1e-6 relative (one pixel of the 100x70 first frame), mean <= 1.7e-7 relative,
// for every sequence and setting below. The tolerance leaves ~15x room for GPUs with less exact
// division and sqrt; VulkanBmfr.ToleranceCatchesRealBugs checks that a missing feature, an
// unshifted block grid or a 20 % different noise amplitude each exceed it at least tenfold.
// Without regularization (noiseAmount = 0) rank-deficient blocks make the fit ill-conditioned
// and the backends differ by up to 1e-2 relative: that case is checked analytically instead
// (VulkanBmfr.ReproducesAFeatureLinearImageWithoutRegularization).
constexpr double kBmfrMaxRel = 5e-5, kBmfrMeanRel = 2e-6;

BmfrSettings settingsFrom(const std::vector<std::string>& list) {
  auto cpu = Device::create({.backend = Backend::Cpu, .threads = 1})->createDenoiser("bmfr");
  // The synthetic scene at ~100 pixels spans ~6 world units: the authors' Sponza position
  // tolerance (0.04) would reject most history, 0.3 keeps it (as the CPU tests do).
  cpu->set("positionTolerance", "0.3");
  for (const auto& s : list) {
    const auto eq = s.find('=');
    cpu->set(s.substr(0, eq), s.substr(eq + 1));
  }
  return cpu->getSettings<BmfrSettings>();
}

std::vector<Frame> frames(int count, int w, int h, bool materialIds) {
  auto seq = syntheticFrames(count, w, h);
  if (materialIds)  // the synthetic scene has no material ids: one per object
    for (Frame& f : seq) f[Buffer::MaterialId] = f[Buffer::ObjectId];
  return seq;
}

// Runs both backends over the sequence and returns the worst relative errors seen.
struct Worst {
  double maxRel = 0, meanRel = 0;
};

Worst runBoth(const BmfrSettings& s, const std::vector<Frame>& seq, const std::string& what, bool check = true) {
  auto cpuDevice = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto cpu = cpuDevice->createDenoiser("bmfr");
  auto gpu = vulkanDevice()->createDenoiser("bmfr");
  cpu->setSettings(s);
  gpu->setSettings(s);
  Worst worst;
  for (size_t i = 0; i < seq.size(); ++i) {
    const Frame& f = seq[i];
    Image a(f.width, f.height, 3), b(f.width, f.height, 3);
    cpu->denoise(f.inputs(), a.view());
    gpu->denoise(f.inputs(), b.view());
    const std::string label = what + ", frame " + std::to_string(i);
    const ErrorStats e = compare(b, a);
    for (int c = 0; c < 3; ++c) {
      worst.maxRel = std::max(worst.maxRel, e.maxAbs[c] / e.maxRef);
      worst.meanRel = std::max(worst.meanRel, e.meanAbs[c] / e.maxRef);
    }
    if (check) expectClose(b, a, kBmfrMaxRel, kBmfrMeanRel, label);
  }
  if (check) std::printf("[ bmfr vulkan ] %s: max %.2e mean %.2e (relative to max|ref|)\n", what.c_str(), worst.maxRel, worst.meanRel);
  return worst;
}

TEST(VulkanBmfr, IsRegisteredOnVulkan) {
  bool found = false;
  for (const auto& m : listMethods())
    if (m.name == "bmfr") found = m.vulkan && m.cpu;
  EXPECT_TRUE(found);
}

// Pass by pass: on a first frame phase I is the identity, so with phase III and TAA off the
// output is the fit and synthesis alone (remodulated).
TEST(VulkanBmfr, FitAndSynthesisMatchCpuOnAFirstFrame) {
  RTD_REQUIRE_VULKAN();
  const BmfrSettings s = settingsFrom({"accumulateFiltered=false", "taa=false"});
  runBoth(s, frames(1, kWidth, kHeight, false), "fit 67x41");
  runBoth(s, frames(1, 100, 70, false), "fit 100x70");
}

// Phase I then phase III with no fit between them: the second accumulation's taps and counts.
TEST(VulkanBmfr, SecondAccumulationMatchesCpu) {
  RTD_REQUIRE_VULKAN();
  runBoth(settingsFrom({"fit=false", "taa=false"}), frames(4, kWidth, kHeight, false), "phase III");
}

TEST(VulkanBmfr, MatchesCpuOverASequence) {
  RTD_REQUIRE_VULKAN();
  runBoth(settingsFrom({}), frames(5, kWidth, kHeight, false), "defaults 67x41");
  runBoth(settingsFrom({}), frames(5, 100, 70, false), "defaults 100x70");
}

// Images smaller than one block: every block is mirrored on both sides (clamped mirroring).
TEST(VulkanBmfr, MatchesCpuOnImagesSmallerThanABlock) {
  RTD_REQUIRE_VULKAN();
  for (const char* block : {"blockSize=32", "blockSize=64"}) {
    runBoth(settingsFrom({block}), frames(2, 5, 3, false), std::string("5x3, ") + block);
    runBoth(settingsFrom({block}), frames(2, 40, 17, false), std::string("40x17, ") + block);
  }
}

TEST(VulkanBmfr, MatchesCpuWith64BlocksAndSamplesPerBlock) {
  RTD_REQUIRE_VULKAN();
  runBoth(settingsFrom({"blockSize=64"}), frames(3, 100, 70, false), "64 blocks");
  runBoth(settingsFrom({"blockSize=64", "samplesPerBlock=36"}), frames(4, 100, 70, false), "64 blocks, 36 samples");
  runBoth(settingsFrom({"samplesPerBlock=200", "taa=false"}), frames(3, kWidth, kHeight, false), "32 blocks, 200 samples");
}

TEST(VulkanBmfr, MatchesCpuWithOtherFeatureSets) {
  RTD_REQUIRE_VULKAN();
  // Every optional feature (12 columns + 3 channels: the most the shaders hold), more noise.
  runBoth(settingsFrom({"featureMaterialId=true", "featureRoughness=true", "noiseAmount=0.05"}),
          frames(3, 100, 70, true), "all features");
  // No squares, no offsets.
  runBoth(settingsFrom({"featurePositionSquared=false", "blockOffsets=false"}), frames(3, kWidth, kHeight, false),
          "no squares, no offsets");
  runBoth(settingsFrom({"featureNormal=false", "featurePosition=false", "demodulate=false"}),
          frames(3, kWidth, kHeight, false), "squares only");
}

// The wall's z and the floor's y with rounding noise of +-1 ulp and +-1e-7 (as a ray caster's
// o + t d gives them, whatever the compiler's contraction): both backends judge those channels
// and their squares constant on the blocks that see only the wall or the floor.
TEST(VulkanBmfr, MatchesCpuWithRoundingNoiseInConstantPositions) {
  RTD_REQUIRE_VULKAN();
  auto seq = frames(3, 100, 70, false);
  for (Frame& f : seq)
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        float* w = f[Buffer::Position].pixel(x, y);
        const int k = (x * 31 + y * 17) % 3 - 1;  // -1, 0, 1
        if (std::abs(w[2] + 4.0f) < 1e-5f) w[2] = k ? std::nextafter(-4.0f, float(k) * 8.0f) : -4.0f;
        if (std::abs(w[1]) < 1e-5f) w[1] = 1e-7f * float(k);
      }
  runBoth(settingsFrom({}), seq, "rounding noise 100x70");
}

// Independent of the CPU: a colour that is exactly albedo * (a combination of [1, n, w, w^2])
// is reproduced by the fit of a first frame without regularization (the flat walls' constant
// features are rank-deficient: their pivots must be dropped, not divided by).
TEST(VulkanBmfr, ReproducesAFeatureLinearImageWithoutRegularization) {
  RTD_REQUIRE_VULKAN();
  for (const char* block : {"32", "64"}) {
    Frame f = frames(1, 100, 70, false)[0];
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const float* n = f[Buffer::Normal].pixel(x, y);
        const float* w = f[Buffer::Position].pixel(x, y);
        const float illumination =
            0.6f + 0.3f * n[1] + 0.2f * n[2] + 0.05f * w[0] - 0.04f * w[2] + 0.01f * w[0] * w[0] + 0.02f * w[1] * w[1];
        for (int c = 0; c < 3; ++c) {
          const float a = f[Buffer::Albedo].at(x, y, c);
          f[Buffer::Color].at(x, y, c) = illumination * (a > 1e-3f ? a : 1.0f);
        }
      }
    auto gpu = vulkanDevice()->createDenoiser("bmfr");
    gpu->setSettings(settingsFrom({"noiseAmount=0", "accumulateFiltered=false", "taa=false", std::string("blockSize=") + block}));
    Image out(f.width, f.height, 3);
    gpu->denoise(f.inputs(), out.view());
    ASSERT_EQ(f[Buffer::Color].channels, 3);
    double err = 0, norm = 0;
    for (size_t i = 0; i < out.pixels.size(); ++i) {
      const double d = double(out.pixels[i]) - f[Buffer::Color].pixels[i];
      err += d * d;
      norm += double(f[Buffer::Color].pixels[i]) * f[Buffer::Color].pixels[i];
    }
    // The CPU test Bmfr.LinearCombination... asserts the same bound.
    std::printf("[ bmfr vulkan ] feature-linear image, %s blocks, no noise: relative RMSE %.2e\n", block, std::sqrt(err / norm));
    EXPECT_LT(std::sqrt(err / norm), 1e-5) << "block " << block;
  }
}

// Issue 12: emitter rows weigh 0 in the fits and emitter pixels keep their phase I value. The
// lamp (emission 2, so that max|ref| stays near the scene's) covers whole 32x32 blocks, so some
// sub-sampled blocks see emitter rows only (which they then keep).
TEST(VulkanBmfr, MatchesCpuWithEmitters) {
  RTD_REQUIRE_VULKAN();
  auto seq = frames(4, 100, 70, false);
  for (Frame& f : seq) {
    f[Buffer::Emission] = Image(f.width, f.height, 3, 0.0f);
    for (int y = 5; y < 55; ++y)
      for (int x = 20; x < 75; ++x)
        for (int c = 0; c < 3; ++c) {
          f[Buffer::Emission].at(x, y, c) = 2.0f;
          f[Buffer::Color].at(x, y, c) += 2.0f;
        }
  }
  runBoth(settingsFrom({}), seq, "emitters 100x70");
  runBoth(settingsFrom({"samplesPerBlock=36"}), seq, "emitters, 36 samples");
  runBoth(settingsFrom({"excludeEmitters=false"}), seq, "emitters filtered");
}

// The tolerance would catch real bugs: the CPU against itself with one thing wrong differs by
// far more than kBmfrMaxRel / kBmfrMeanRel.
TEST(VulkanBmfr, ToleranceCatchesRealBugs) {
  const auto seq = frames(3, 100, 70, false);
  auto run = [&](const BmfrSettings& s) {
    auto d = Device::create({.backend = Backend::Cpu, .threads = 1})->createDenoiser("bmfr");
    d->setSettings(s);
    std::vector<Image> out;
    for (const Frame& f : seq) {
      out.emplace_back(f.width, f.height, 3);
      d->denoise(f.inputs(), out.back().view());
    }
    return out;
  };
  const auto reference = run(settingsFrom({}));
  const std::vector<std::pair<std::string, BmfrSettings>> bugs = {
      {"a missing feature (w^2)", settingsFrom({"featurePositionSquared=false"})},
      {"no block offsets (a wrong grid)", settingsFrom({"blockOffsets=false"})},
      {"other regularization noise (eps 0.012)", settingsFrom({"noiseAmount=0.012"})},
  };
  for (const auto& [what, s] : bugs) {
    const auto wrong = run(s);
    const ErrorStats e = compare(wrong.back(), reference.back());
    double maxRel = 0, meanRel = 0;
    for (int c = 0; c < 3; ++c) {
      maxRel = std::max(maxRel, e.maxAbs[c] / e.maxRef);
      meanRel = std::max(meanRel, e.meanAbs[c] / e.maxRef);
    }
    EXPECT_GT(maxRel, 10 * kBmfrMaxRel) << what << ": " << describe(e);
    EXPECT_GT(meanRel, 10 * kBmfrMeanRel) << what << ": " << describe(e);
  }
}

// Above the scratch buffer's cap (128 MiB, or a smaller maxStorageBufferRange; ~4K frames) the
// blocks are fitted in several dispatches that reuse the buffer. Here a device whose limit holds
// three blocks' matrices fits the 100x70 frame's 20 blocks in seven dispatches: each block's
// work is the same wherever it sits in the buffer, so the output is the one-dispatch output bit
// for bit, frame after frame (the phase I history and the block offsets move between frames).
TEST(VulkanBmfr, FitInSeveralDispatchesMatchesOneDispatch) {
  RTD_REQUIRE_VULKAN();
  auto whole = vulkanDevice()->createDenoiser("bmfr");
  auto cappedDevice = Device::create({.backend = Backend::Vulkan});
  auto capped = cappedDevice->createDenoiser("bmfr");
  for (Denoiser* d : {whole.get(), capped.get()}) d->set("positionTolerance", "0.3");
  // The default features: 10 columns + 3 channels of 32 x 32 rows, 53248 bytes a block.
  constexpr uint32_t kBlockBytes = 13 * 1024 * 4;
  dynamic_cast<vk::VulkanDenoiserBase&>(*capped).context().capStorageBufferRange(3 * kBlockBytes + 1000);
  const auto seq = frames(4, 100, 70, false);
  for (size_t i = 0; i < seq.size(); ++i) {
    Image a(100, 70, 3), b(100, 70, 3);
    whole->denoise(seq[i].inputs(), a.view());
    capped->denoise(seq[i].inputs(), b.view());
    const ErrorStats e = compare(b, a);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(e.maxAbs[c], 0.0) << "frame " << i << ", channel " << c;
  }
  // The cap took: the capped denoiser's scratch holds 3 blocks, the other's all 20 (with room
  // for the largest settings' matrices).
  EXPECT_LT(memoryTotal(capped->stats()) + 17 * uint64_t(kBlockBytes), memoryTotal(whole->stats()));
}

}  // namespace
}  // namespace rtd::test
#endif
