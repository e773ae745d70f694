// FrameStats::memory on the Vulkan backend: every method's report adds up to the device memory
// its denoiser holds (the context's count of live buffers is the reference), nothing is left
// when the denoiser is gone, and the imported frames are the CPU's frames on the GPU.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "backend/vulkan/vulkan_denoiser.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

std::map<std::string, uint64_t> byCategory(const FrameStats& stats) {
  std::map<std::string, uint64_t> m;
  for (const MemoryUse& u : stats.memory) m[u.category] += u.bytes;
  return m;
}

vk::Context& contextOf(Denoiser& d) { return dynamic_cast<vk::VulkanDenoiserBase&>(d).context(); }

// Every Vulkan method with its defaults, and the SVGF variants whose parts allocate on their
// own (Voorhuis's reflections, Gersthofer's pipeline, Dundr's progressive mode): two frames,
// then the report against the buffers alive on the context.
TEST(VulkanMemory, EveryMethodsReportIsAllTheDeviceMemoryItsDenoiserHolds) {
  RTD_REQUIRE_VULKAN();
  std::vector<std::pair<std::string, std::string>> cases;  // method, svgf variant
  for (const MethodInfo& m : listMethods())
    if (m.vulkan) cases.push_back({m.name, ""});
  for (const char* v : {"voorhuis", "gersthofer", "dundr"}) cases.push_back({"svgf", v});
  ASSERT_GE(cases.size(), 6u);
  const auto frames = syntheticFrames(2);
  auto probe = vulkanDevice()->createDenoiser("accumulate");  // the device's context
  vk::Context& ctx = contextOf(*probe);
  for (const auto& [method, variant] : cases) {
    const std::string what = method + (variant.empty() ? "" : " (" + variant + ")");
    const uint64_t before = ctx.liveBytes();
    {
      auto d = vulkanDevice()->createDenoiser(method);
      if (!variant.empty()) d->set("variant", variant);
      Image out(kWidth, kHeight, 3);
      for (const Frame& f : frames) d->denoise(f.inputs(), out.view());
      const auto m = byCategory(d->stats());
      EXPECT_EQ(memoryTotal(d->stats()), ctx.liveBytes() - before) << what << ": a buffer the report misses or counts twice";
      // Two frames of at least colour (3 planes) each; upload, read-back and counters.
      EXPECT_GE(m.count("frames") ? m.at("frames") : 0, 2u * 3 * 4 * kWidth * kHeight) << what;
      EXPECT_GE(m.count("staging") ? m.at("staging") : 0, 3u * 4 * kWidth * kHeight) << what;
      EXPECT_GT(m.count("planes") ? m.at("planes") : 0, 0u) << what;
    }
    EXPECT_EQ(ctx.liveBytes(), before) << what << ": device memory left after the denoiser is gone";
  }
}

// The frames a Vulkan denoiser keeps are the CPU denoiser's imported frames (the same buffers,
// current and previous) plus the two cameras, each rounded up at most to the device's
// alignment; at twice the size they take four times the memory.
TEST(VulkanMemory, FramesAreTheCpusImportedFrames) {
  RTD_REQUIRE_VULKAN();
  for (int scale : {1, 2}) {
    const int w = kWidth * scale, h = kHeight * scale;
    const auto frames = syntheticFrames(2, w, h);
    auto cpu = Device::create({.backend = Backend::Cpu, .threads = 1})->createDenoiser("svgf");
    auto gpu = vulkanDevice()->createDenoiser("svgf");
    Image out(w, h, 3);
    for (const Frame& f : frames) {
      cpu->denoise(f.inputs(), out.view());
      gpu->denoise(f.inputs(), out.view());
    }
    const uint64_t cpuFrames = byCategory(cpu->stats()).at("frames"), gpuFrames = byCategory(gpu->stats()).at("frames");
    const uint64_t cameras = 2 * 32 * sizeof(float), slack = 2 * kBufferCount * 256;
    EXPECT_GE(gpuFrames, cpuFrames + cameras) << scale;
    EXPECT_LE(gpuFrames, cpuFrames + cameras + slack) << scale;
    EXPECT_GE(cpuFrames, 2u * 10 * 4 * w * h) << scale << ": colour, albedo, normal, depth, motion... in two frames";
  }
}

// TAA's planes are allocated when TAA first runs, as on the CPU: switching it on adds exactly
// them, each rounded up at most to the device's alignment. They are two history sets and the
// decoded output (9 planes) and the surface keys (one plane of uint32: taaOwnSurface, on the
// synthetic frames' object ids).
TEST(VulkanMemory, TaaPlanesAreAllocatedWhenTaaFirstRuns) {
  RTD_REQUIRE_VULKAN();
  const auto frames = syntheticFrames(3);
  auto d = vulkanDevice()->createDenoiser("svgf");
  d->set("taa", "false");
  Image out(kWidth, kHeight, 3);
  for (int i = 0; i < 2; ++i) d->denoise(frames[size_t(i)].inputs(), out.view());
  const uint64_t without = byCategory(d->stats()).at("planes");
  d->set("taa", "true");
  d->denoise(frames[2].inputs(), out.view());
  const uint64_t with = byCategory(d->stats()).at("planes"), taa = 10u * 4 * kWidth * kHeight;
  EXPECT_GE(with - without, taa);
  EXPECT_LE(with - without, taa + 4 * 256);
}

}  // namespace
}  // namespace rtd::test
