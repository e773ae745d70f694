// Method "svgf" on Vulkan against the CPU over short sequences, for each paper's variant and the
// split-component modes, on 67x41 (not a multiple of the 16x16 workgroup).
#if __has_include("rtd/methods/svgf.h")
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// Tolerance: kSvgfMaxRel, kSvgfMeanRel (vulkan_test_util.h).

// FXAA (the gersthofer preset) flips a few edge decisions on inputs that differ by ~1e-6:
// up to 1 % of the pixels may differ more (measured on lavapipe: at most 9 of 2747, 0.33 %), the others
// keep the tolerance above.
constexpr double kFlippedShare = 0.01;

// `splitFrom`: the frames before it have the colour only (the second stream appears then).
void runBoth(const std::vector<std::string>& settings, bool split, int frames, const std::string& what,
             bool emission = false, bool decisions = false, bool reflectanceless = false, int splitFrom = 0) {
  auto cpuDevice = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto cpu = cpuDevice->createDenoiser("svgf");
  auto gpu = vulkanDevice()->createDenoiser("svgf");
  for (const auto& s : settings) {
    const auto eq = s.find('=');
    cpu->set(s.substr(0, eq), s.substr(eq + 1));
    gpu->set(s.substr(0, eq), s.substr(eq + 1));
  }
  auto seq = syntheticFrames(frames);
  for (size_t i = 0; i < seq.size(); ++i) {
    Frame& f = seq[i];
    if (split && int(i) >= splitFrom) {  // diffuse 70 % and specular 30 % of the colour: two streams
      f[Buffer::Diffuse] = f[Buffer::Color];
      f[Buffer::Specular] = f[Buffer::Color];
      for (auto& v : f[Buffer::Diffuse].pixels) v *= 0.7f;
      for (auto& v : f[Buffer::Specular].pixels) v *= 0.3f;
    }
    if (emission) {  // a bright emitter, part of color and (as the renderer counts it) diffuse
      f[Buffer::Emission] = Image(f.width, f.height, 3, 0.0f);
      for (int y = 10; y < 20; ++y)
        for (int x = 30; x < 40; ++x)
          for (int c = 0; c < 3; ++c) {
            f[Buffer::Emission].at(x, y, c) = 20.0f;
            f[Buffer::Color].at(x, y, c) += 20.0f;
            if (split) f[Buffer::Diffuse].at(x, y, c) += 20.0f;
            // Half the lamp as Cycles writes a surface without a BSDF: its emission as the
            // albedo (out of the guide with excludeEmitters off too), the other half a lamp
            // with a reflectance (in it).
            if (reflectanceless && x < 35) f[Buffer::Albedo].at(x, y, c) = 20.0f;
          }
    }
    Image a(f.width, f.height, 3), b(f.width, f.height, 3);
    cpu->denoise(f.inputs(), a.view());
    gpu->denoise(f.inputs(), b.view());
    if (decisions) expectCloseExceptFlips(b, a, kSvgfMaxRel, kSvgfMeanRel, kFlippedShare, what + ", frame " + std::to_string(i));
    else expectClose(b, a, kSvgfMaxRel, kSvgfMeanRel, what + ", frame " + std::to_string(i));
  }
}

TEST(VulkanSvgf, MatchesCpuSchied) {
  RTD_REQUIRE_VULKAN();
  runBoth({}, false, 6, "schied");
}
TEST(VulkanSvgf, MatchesCpuWithSeparatedEmission) {
  RTD_REQUIRE_VULKAN();
  // Emitter pixels filtered like any surface (the default), and out of the guide (issue 12).
  runBoth({}, false, 4, "emission", true);
  runBoth({"excludeEmitters=true"}, false, 4, "emission, emitters excluded", true);
  runBoth({"variant=gersthofer", "fxaa=false", "excludeEmitters=true"}, false, 4, "gersthofer, emitters excluded", true);
  runBoth({"variant=voorhuisRobustness"}, true, 4, "emission, diffuse/specular", true);
  runBoth({}, false, 4, "emission, emitters without a reflectance", true, false, true);
  runBoth({"variant=gersthofer", "fxaa=false"}, false, 4, "gersthofer, emitters without a reflectance", true, false, true);
}
TEST(VulkanSvgf, MatchesCpuDundr) {
  RTD_REQUIRE_VULKAN();
  runBoth({"variant=dundr"}, false, 5, "dundr");
  runBoth({"variant=dundr", "components=diffuse"}, true, 4, "dundr, diffuse filtered, specular unfiltered");
}
TEST(VulkanSvgf, MatchesCpuGersthofer) {
  RTD_REQUIRE_VULKAN();
  // The composite pipeline up to the output, then with FXAA and the ACES tone map.
  runBoth({"variant=gersthofer", "fxaa=false"}, false, 5, "gersthofer without fxaa");
  runBoth({"variant=gersthofer", "toneMap=aces"}, false, 5, "gersthofer", true, true);
}
TEST(VulkanSvgf, MatchesCpuVoorhuisWithSplitComponents) {
  RTD_REQUIRE_VULKAN();
  runBoth({"variant=voorhuisRobustness"}, true, 5, "voorhuis, diffuse/specular");
}
// Each stream's history is allocated when the input first has the stream (svgf.cpp,
// svgf_vulkan.cpp): the diffuse / specular split appears at the third frame, the median's planes
// with the first frame that has the lobes (voorhuis's fireflyMedian).
TEST(VulkanSvgf, MatchesCpuWhereTheSecondStreamAppearsMidSequence) {
  RTD_REQUIRE_VULKAN();
  runBoth({"variant=dundr"}, true, 5, "dundr, split from frame 2", false, false, false, 2);
  runBoth({"variant=voorhuisRobustness"}, true, 5, "voorhuis, split from frame 2", false, false, false, 2);
}
TEST(VulkanSvgf, MatchesCpuWithoutTaaAndVarianceFiltering) {
  RTD_REQUIRE_VULKAN();
  runBoth({"taa=false", "varianceFiltering=false", "maxDepthSlope=0.5", "atrousIterations=3"}, false, 4, "options");
}
// Where the CPU's last a-trous level cannot write the remodulated output itself (it is fed
// back, or there is no level), its own pass does (svgf::Filter::run's fallback).
TEST(VulkanSvgf, MatchesCpuWhereTheLastLevelIsFedBackOrAbsent) {
  RTD_REQUIRE_VULKAN();
  runBoth({"feedbackLevel=5"}, false, 4, "last level fed back");
  runBoth({"atrousIterations=0", "feedbackLevel=0"}, false, 4, "no a-trous level");
}

}  // namespace
}  // namespace rtd::test
#endif
