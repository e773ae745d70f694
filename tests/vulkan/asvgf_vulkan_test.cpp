// Method "asvgf" on Vulkan against the CPU over short sequences of the synthetic scene at 67x41
// (not a multiple of the workgroup or of the 3x3 strata), with the sun switched off midway so
// the gradients, the adaptive history and their a-trous levels all matter.
#if __has_include("rtd/methods/asvgf.h")
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// Tolerance: SVGF's (kSvgfMaxRel, kSvgfMeanRel in vulkan_test_util.h): the shared filter's weights differ by ~1e-6 relative
// between the backends' exp() and division, and the feedback loop carries that on; the gradient
// passes add float sums in a different order (historyAntilag) and pow() by squaring on both.
// Measured on lavapipe: max 3e-6 absolute (5e-7 of max|ref| = 5.7), mean below 1e-6.
void runBoth(const std::vector<std::string>& settings, const std::string& what, bool gradientSamples = true,
             bool reflectedNormals = false) {
  auto cpuDevice = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto cpu = cpuDevice->createDenoiser("asvgf");
  auto gpu = vulkanDevice()->createDenoiser("asvgf");
  for (const auto& s : settings) {
    const auto eq = s.find('=');
    cpu->set(s.substr(0, eq), s.substr(eq + 1));
    gpu->set(s.substr(0, eq), s.substr(eq + 1));
  }
  synthetic::Scene scene;
  scene.width = kWidth;
  scene.height = kHeight;
  scene.sunOffFrame = 3;
  scene.gradientSamples = gradientSamples;
  for (int i = 0; i < 6; ++i) {
    Frame f = synthetic::makeFrame(scene, i);
    if (reflectedNormals) {  // "mirror" pixels in a band: another normal for the filter
      f[Buffer::ReflectedNormal] = Image(f.width, f.height, 3, 0.0f);
      for (int y = 5; y < 25; ++y)
        for (int x = 10; x < 40; ++x) f[Buffer::ReflectedNormal].at(x, y, x < 25 ? 0 : 1) = 1.0f;
    }
    Image a(f.width, f.height, 3), b(f.width, f.height, 3);
    cpu->denoise(f.inputs(), a.view());
    gpu->denoise(f.inputs(), b.view());
    expectClose(b, a, kSvgfMaxRel, kSvgfMeanRel, what + ", frame " + std::to_string(i));
  }
}

TEST(VulkanAsvgf, MatchesCpuWithGradientSamples) {
  RTD_REQUIRE_VULKAN();
  runBoth({}, "defaults");
}
TEST(VulkanAsvgf, MatchesCpuWithReflectedNormals) {
  RTD_REQUIRE_VULKAN();
  runBoth({}, "reflected normals", true, true);
  runBoth({"reflectedNormals=false"}, "reflected normals off", true, true);
}
TEST(VulkanAsvgf, MatchesCpuWithTheHistoryAntilagEstimate) {
  RTD_REQUIRE_VULKAN();
  runBoth({"gradientSource=historyAntilag"}, "historyAntilag", false);
}
TEST(VulkanAsvgf, MatchesCpuWithOtherSettings) {
  RTD_REQUIRE_VULKAN();
  runBoth({"gradientIterations=0", "taa=false", "antilagScale=3", "historyExponent=2.5", "minAlphaColor=0"},
          "options");
}

}  // namespace
}  // namespace rtd::test
#endif
