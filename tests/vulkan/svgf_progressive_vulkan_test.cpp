// Method "svgf" on Vulkan in Dundr's progressive sub-1-spp mode (Sec. 5, useSampleMask) against
// the CPU: a quarter of the pixels sampled per frame in a pattern that rotates over four frames,
// on a moving-camera sequence at 67x41 (not a multiple of the 16x16 workgroup).
#if __has_include("rtd/methods/svgf.h")
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// Pixel (x, y) is sampled in frame f when its position in a 2x2 block comes up: (x & 1) +
// 2 (y & 1) == f mod 4. Unsampled pixels get colour 0 and sampleMask 0, as the renderer writes
// them; features stay complete (docs/renderer.md).
bool sampled(int x, int y, int frame) { return ((x & 1) + 2 * (y & 1)) == frame % 4; }

std::vector<Frame> maskedFrames(int count, bool split) {
  auto seq = syntheticFrames(count);
  for (int i = 0; i < count; ++i) {
    Frame& f = seq[size_t(i)];
    Image mask(f.width, f.height, 1, 0.0f);
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        if (sampled(x, y, i)) {
          mask.at(x, y, 0) = 1.0f;
          continue;
        }
        for (int c = 0; c < 3; ++c) f[Buffer::Color].at(x, y, c) = 0.0f;
      }
    f[Buffer::SampleMask] = mask;
    if (split) {  // diffuse 70 % and specular 30 % of the colour: two streams
      f[Buffer::Diffuse] = f[Buffer::Color];
      f[Buffer::Specular] = f[Buffer::Color];
      for (auto& v : f[Buffer::Diffuse].pixels) v *= 0.7f;
      for (auto& v : f[Buffer::Specular].pixels) v *= 0.3f;
    }
  }
  return seq;
}

std::unique_ptr<Denoiser> make(Device& device, const std::vector<std::string>& settings) {
  auto d = device.createDenoiser("svgf");
  for (const auto& s : settings) {
    const auto eq = s.find('=');
    d->set(s.substr(0, eq), s.substr(eq + 1));
  }
  return d;
}

// Runs the CPU and the GPU on the masked sequence, checks every frame against the stated
// tolerance and returns the GPU's last frame.
Image runBothProgressive(const std::vector<std::string>& settings, bool split, int frames, const std::string& what) {
  auto cpuDevice = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto cpu = make(*cpuDevice, settings);
  auto gpu = make(*vulkanDevice(), settings);
  Image b;
  auto seq = maskedFrames(frames, split);
  for (size_t i = 0; i < seq.size(); ++i) {
    Image a(kWidth, kHeight, 3);
    b = Image(kWidth, kHeight, 3);
    cpu->denoise(seq[i].inputs(), a.view());
    gpu->denoise(seq[i].inputs(), b.view());
    expectClose(b, a, kSvgfMaxRel, kSvgfMeanRel, what + ", frame " + std::to_string(i));
  }
  return b;
}

TEST(VulkanSvgfProgressive, MatchesCpuSchied) {
  RTD_REQUIRE_VULKAN();
  runBothProgressive({}, false, 6, "schied, sample mask");
}
TEST(VulkanSvgfProgressive, MatchesCpuDundr) {
  RTD_REQUIRE_VULKAN();
  runBothProgressive({"variant=dundr"}, false, 6, "dundr, sample mask");
}
TEST(VulkanSvgfProgressive, MatchesCpuVoorhuisWithSplitComponents) {
  // Two streams share the validity planes; feedback level 2, no variance filtering of indirect.
  RTD_REQUIRE_VULKAN();
  runBothProgressive({"variant=voorhuisRobustness", "feedbackLevel=2"}, true, 5, "voorhuis, diffuse/specular, sample mask");
}

// The mask is really used: the same sequence with useSampleMask off (every pixel taken as
// sampled, its colour 0 where it was not traced) gives a clearly different image on the GPU,
// and that dense result also matches the CPU with the setting off.
TEST(VulkanSvgfProgressive, MaskChangesTheResult) {
  RTD_REQUIRE_VULKAN();
  const Image masked = runBothProgressive({}, false, 5, "sample mask");
  const Image dense = runBothProgressive({"useSampleMask=false"}, false, 5, "sample mask ignored");
  const ErrorStats s = compare(dense, masked);
  // Treating empty pixels as black samples darkens the image by about the unsampled share.
  for (int c = 0; c < 3; ++c) EXPECT_GT(s.meanAbs[c], 0.05 * s.maxRef) << describe(s);
  double sumMasked = 0, sumDense = 0;
  for (float v : masked.pixels) sumMasked += v;
  for (float v : dense.pixels) sumDense += v;
  EXPECT_LT(sumDense, 0.8 * sumMasked) << "black non-samples should darken the dense result";
}

}  // namespace
}  // namespace rtd::test
#endif
