// Method "accumulate" on Vulkan against the CPU, frame by frame over short sequences, with the
// reprojection driven by motion vectors, by the camera, with and without albedo, strided views
// and int32 ids, a camera cut and a resize.
#include <cstring>

#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// Runs the same frames through a CPU and a Vulkan denoiser with the same settings and checks
// every output. `edit` may drop or change buffers of a frame's inputs.
template <class Edit>
void runBoth(const std::vector<Frame>& frames, const std::vector<std::string>& settings, Edit edit,
             const std::string& what, double maxRel = 1e-4, double meanRel = 1e-6) {
  auto cpuDevice = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto cpu = cpuDevice->createDenoiser("accumulate");
  auto gpu = vulkanDevice()->createDenoiser("accumulate");
  for (const auto& s : settings) {
    const auto eq = s.find('=');
    cpu->set(s.substr(0, eq), s.substr(eq + 1));
    gpu->set(s.substr(0, eq), s.substr(eq + 1));
  }
  for (size_t i = 0; i < frames.size(); ++i) {
    FrameInputs in = frames[i].inputs();
    edit(int(i), in);
    Image a(frames[i].width, frames[i].height, 3), b(frames[i].width, frames[i].height, 4);
    cpu->denoise(in, a.view());
    gpu->denoise(in, b.view());  // Float4 output: alpha must be 1
    expectClose(b, a, maxRel, meanRel, what + ", frame " + std::to_string(i));
    for (size_t p = 0; p < size_t(b.width) * b.height; ++p) ASSERT_EQ(b.pixels[p * 4 + 3], 1.0f);
  }
}

TEST(VulkanAccumulate, MatchesCpuWithMotionVectors) {
  RTD_REQUIRE_VULKAN();
  runBoth(syntheticFrames(6), {}, [](int, FrameInputs&) {}, "motion vectors");
}

TEST(VulkanAccumulate, MatchesCpuWithCameraReprojectionAndPositionTest) {
  RTD_REQUIRE_VULKAN();
  // No motion buffer: motion comes from projecting positions with the previous camera.
  runBoth(syntheticFrames(6), {"positionTolerance=0.05"}, [](int, FrameInputs& in) { in[Buffer::Motion] = {}; },
          "camera reprojection");
}

TEST(VulkanAccumulate, MatchesCpuWithoutFeaturesOrAlbedo) {
  RTD_REQUIRE_VULKAN();
  runBoth(syntheticFrames(5), {"demodulate=false", "fallback3x3=false", "alpha=0.3"},
          [](int, FrameInputs& in) {
            in[Buffer::Normal] = {};
            in[Buffer::ObjectId] = {};
          },
          "no normals, no ids, no albedo");
}

TEST(VulkanAccumulate, StridedViewsAndInt32IdsImportLikeTightOnes) {
  RTD_REQUIRE_VULKAN();
  auto frames = syntheticFrames(4);
  // Colour as RGBA with a padded row, ids as int32: the import shader applies the strides.
  std::vector<std::vector<float>> rgba(frames.size());
  std::vector<std::vector<int32_t>> ids(frames.size());
  runBoth(frames, {},
          [&](int i, FrameInputs& in) {
            const Frame& f = frames[size_t(i)];
            const size_t row = size_t(f.width) * 4 + 3;
            rgba[size_t(i)].assign(row * f.height, -7.0f);
            ids[size_t(i)].resize(size_t(f.width) * f.height);
            for (int y = 0; y < f.height; ++y)
              for (int x = 0; x < f.width; ++x) {
                std::memcpy(&rgba[size_t(i)][y * row + x * 4], f[Buffer::Color].pixel(x, y), 12);
                ids[size_t(i)][size_t(y) * f.width + x] = int32_t(f[Buffer::ObjectId].at(x, y));
              }
            in[Buffer::Color] = {rgba[size_t(i)].data(), f.width, f.height, Format::Float4, 16, row * 4};
            in[Buffer::ObjectId] = {ids[size_t(i)].data(), f.width, f.height, Format::Int32, 0, 0};
          },
          "strided colour, int32 ids");
}

TEST(VulkanAccumulate, CameraCutAndResizeRestartHistory) {
  RTD_REQUIRE_VULKAN();
  auto small = syntheticFrames(3), large = syntheticFrames(3, 35, 19);
  std::vector<Frame> frames = small;
  frames.insert(frames.end(), large.begin(), large.end());
  frames.push_back(small[0]);
  runBoth(frames, {}, [](int i, FrameInputs& in) { in.cameraCut = i == 2; }, "cut and resize");
}

TEST(VulkanAccumulate, SanitizesNanAndNegativeRadianceLikeTheCpu) {
  RTD_REQUIRE_VULKAN();
  auto frames = syntheticFrames(3);
  for (auto& f : frames) {
    f[Buffer::Color].at(3, 4, 0) = std::nanf("");
    f[Buffer::Color].at(10, 20, 1) = -1.0f;
    f[Buffer::Color].at(66, 40, 2) = INFINITY;
  }
  auto gpu = vulkanDevice()->createDenoiser("accumulate");
  Image out(kWidth, kHeight, 3);
  for (auto& f : frames) {
    gpu->denoise(f.inputs(), out.view());
    EXPECT_EQ(gpu->stats().sanitizedValues, 3u);
    for (float v : out.pixels) ASSERT_TRUE(std::isfinite(v));
  }
  runBoth(frames, {}, [](int, FrameInputs&) {}, "with NaN/Inf/negative inputs");
}

TEST(VulkanAccumulate, ReportsGpuTimingsPerPass) {
  RTD_REQUIRE_VULKAN();
  auto gpu = vulkanDevice()->createDenoiser("accumulate");
  auto frames = syntheticFrames(2);
  Image out(kWidth, kHeight, 3);
  for (auto& f : frames) gpu->denoise(f.inputs(), out.view());
  std::vector<std::string> names;
  for (const auto& p : gpu->stats().passes) {
    names.push_back(p.name);
    EXPECT_GE(p.milliseconds, 0.0) << p.name;
  }
  for (const char* want : {"import", "demodulate", "reproject", "accumulate", "remodulate", "export", "gpu total"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
}

}  // namespace
}  // namespace rtd::test
