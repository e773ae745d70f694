// Supersampling with guide rays on Vulkan (Voorhuis 2018 Sec. 5; guide_assign / guide_premix /
// guide_resolve, run by GuideRays::denoise in the denoiser's submission) against the CPU's
// GuideRays::premix / resolve, on lavapipe: the passes alone (around a pass-through filter), the
// constant-radiance energy invariant, errors, the whole Voorhuis pipeline with 4 spp, the CLI.
#if defined(HAVE_RTDENOISE_RENDER)
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "passes/guide_rays_fixtures.h"
#include "render/render_test_util.h"
#include "support/run_cli.h"
#include "rtd/guide_rays.h"
#include "rtd/render/render.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// A pass-through filter on either backend: `accumulate` on its first frame, not demodulated,
// returns its input (plus and minus the separated emission).
std::unique_ptr<Denoiser> passThrough(Device& device) {
  auto d = device.createDenoiser("accumulate");
  d->set("demodulate", "false");
  return d;
}

// The glossy scene (mirrors, gold spheres of roughness 0.05-0.55, a glossy floor) at 4 spp with
// guide rays: frame `index`'s guides and samples.
struct GuideRayFrame {
  Frame guides;
  GuideRaySamples samples;
};
const std::vector<GuideRayFrame>& guideRayFrames() {
  static const std::vector<GuideRayFrame> frames = [] {
    render::RenderSettings rs;
    rs.width = kWidth;
    rs.height = kHeight;
    rs.spp = 4;
    rs.guideRays = true;
    render::Renderer r(render::Scene::load("glossy"), rs);
    std::vector<GuideRayFrame> v(4);
    for (int i = 0; i < 4; ++i) v[size_t(i)].guides = r.render(20 + i, render::Eye::Center, v[size_t(i)].samples);
    return v;
  }();
  return frames;
}

TEST(VulkanGuideRays, PremixAndResolveMatchCpu) {
  // The assignment, Eq. 7 and the copy back alone: CPU premix -> pass-through -> resolve against
  // the same through GuideRays::denoise on Vulkan. The shaders add in the CPU's order without
  // fused multiply-add; measured on lavapipe: identical. Bound: 1e-6 of the largest value.
  RTD_REQUIRE_VULKAN();
  auto cpuDevice = Device::create({.backend = Backend::Cpu, .threads = 1});
  const GuideRayFrame& f = guideRayFrames()[0];
  GuideRays cpuRays, gpuRays;
  const Frame mixed = cpuRays.premix(f.guides, f.samples);
  Image filtered(f.guides.width, f.guides.height, 3);
  passThrough(*cpuDevice)->denoise(mixed.inputs(), filtered.view());
  const Image cpu = cpuRays.resolve(filtered);
  auto gpuFilter = passThrough(*vulkanDevice());
  const Image gpu = gpuRays.denoise(*gpuFilter, f.guides, f.samples);
  // Non-trivial: Eq. 7 changed the colour, most pixels took some sample.
  size_t mixedPixels = 0;
  for (int c : cpuRays.mixCount()) mixedPixels += c > 1;
  EXPECT_GT(mixedPixels, size_t(0.9 * kWidth * kHeight));
  const ErrorStats e = compare(gpu, cpu);
  for (int c = 0; c < 3; ++c) EXPECT_LE(e.maxAbs[c], 1e-6 * e.maxRef) << describe(e);
  // The passes ran in the denoiser's submission and are in its stats; none outside.
  std::vector<std::string> names;
  for (const PassTiming& p : gpuFilter->stats().passes) names.push_back(p.name);
  for (const char* pass : {"guideRays.upload", "guideRays.premix", "guideRays.resolve"})
    EXPECT_NE(std::find(names.begin(), names.end(), pass), names.end()) << pass;
  EXPECT_TRUE(gpuRays.passes().empty());
}

TEST(VulkanGuideRays, ConstantRadianceKeepsItsEnergyForAnySampleCount) {
  // Checklist 22 (a) on Vulkan: whatever the assignment, a constant image stays constant, for
  // 1 to 8 spp (pass-through filter), and through SVGF (Voorhuis preset, TAA off) over 4 frames.
  RTD_REQUIRE_VULKAN();
  const int w = 24, h = 16;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f), z(1.0f, 3.0f);
  GuideRays gr;  // one object for all: its device buffers are reused and resized
  for (int spp : {1, 2, 4, 8}) {
    const Frame g = guideFrame(w, h, [&](float, float) { return z(rng); }, 0.37f);
    const GuideRaySamples s = samplesAt(
        w, h, spp - 1, [&](int, int, int) { return std::pair{u(rng), u(rng)}; }, [&](float, float) { return z(rng); },
        [](float, float) { return 0.37f; });
    auto filter = passThrough(*vulkanDevice());
    const Image out = gr.denoise(*filter, g, s);
    for (float v : out.pixels) ASSERT_NEAR(v, 0.37f, 1e-6f) << spp << " spp";
  }
  const int sw = 32, sh = 20;
  auto svgf = vulkanDevice()->createDenoiser("svgf");
  svgf->set("variant", "voorhuis");
  svgf->set("taa", "false");
  std::uniform_real_distribution<float> z2(1.0f, 1.5f);
  for (int frame = 0; frame < 4; ++frame) {
    Frame g = guideFrame(sw, sh, [&](float x, float y) { return 1.0f + 0.01f * x + 0.02f * y; }, 0.42f);
    g[Buffer::Albedo] = Image(sw, sh, 3, 0.8f);
    g[Buffer::Motion] = Image(sw, sh, 2);
    const GuideRaySamples s = samplesAt(
        sw, sh, 3, [&](int, int, int) { return std::pair{u(rng), u(rng)}; }, [&](float, float) { return z2(rng); },
        [](float, float) { return 0.42f; });
    const Image out = gr.denoise(*svgf, g, s);
    for (float v : out.pixels) ASSERT_NEAR(v, 0.42f, 1e-4f) << "frame " << frame;
  }
}

TEST(VulkanGuideRays, MalformedSamplesAreRefusedBeforeTheDenoiserRuns) {
  // The same checks as premix(): a sample without its normal is an error naming it, and the
  // denoiser's history is untouched (its next frame equals a fresh denoiser's).
  RTD_REQUIRE_VULKAN();
  const GuideRayFrame& f = guideRayFrames()[1];
  GuideRaySamples bad = f.samples;
  bad.samples[1][Buffer::Normal] = Image();
  auto d = vulkanDevice()->createDenoiser("svgf");
  GuideRays gr;
  try {
    gr.denoise(*d, f.guides, bad);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sample 2 has no 'normal'"), std::string::npos) << e.what();
  }
  auto fresh = vulkanDevice()->createDenoiser("svgf");
  GuideRays gr2;
  const ErrorStats e = compare(gr.denoise(*d, f.guides, f.samples), gr2.denoise(*fresh, f.guides, f.samples));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(e.maxAbs[c], 0.0) << describe(e);
}

TEST(VulkanGuideRays, VoorhuisWithGuideRaysMatchesCpu) {
  // The whole Voorhuis pipeline at 4 spp, every pass on Vulkan (pre-mix, SVGF Ours with TAA off,
  // copy back) against the same on the CPU, over 4 frames, within the bounds of the 1-spp
  // comparison (reflections_vulkan_test.cpp: mean |d| <= 2e-5, max <= 2e-2 of the largest value).
  RTD_REQUIRE_VULKAN();
  auto cpuDevice = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto cpu = cpuDevice->createDenoiser("svgf");
  auto gpu = vulkanDevice()->createDenoiser("svgf");
  for (Denoiser* d : {cpu.get(), gpu.get()}) {
    d->set("variant", "voorhuis");
    d->set("taa", "false");
  }
  GuideRays cpuRays, gpuRays;
  for (int i = 0; i < 4; ++i) {
    const GuideRayFrame& f = guideRayFrames()[size_t(i)];
    const Image a = cpuRays.denoise(*cpu, f.guides, f.samples);
    const Image b = gpuRays.denoise(*gpu, f.guides, f.samples);
    EXPECT_EQ(cpu->stats().notes, gpu->stats().notes);
    EXPECT_EQ(cpuRays.passes().size(), 2u);
    const ErrorStats e = compare(b, a);
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(e.meanAbs[c], 2e-5 * e.maxRef) << "frame " << i << ": " << describe(e);
      EXPECT_LE(e.maxAbs[c], 2e-2 * e.maxRef) << "frame " << i << ": " << describe(e);
    }
  }
}

TEST(VulkanGuideRays, CliOnVulkanEqualsTheApiPath) {
  // `rtdenoise denoise --backend vulkan` on a sequence with samples runs GuideRays::denoise on
  // Vulkan: bit for bit the API path on the same device, the passes in timings.json.
  RTD_REQUIRE_VULKAN();
  namespace fs = std::filesystem;
  const int w = 24, h = 16, frames = 2, spp = 3;
  const fs::path dir = render::test::tempDir("guide_cli_vulkan");
  auto r = runCli("render --scene corridorglossy --size 24x16 --frames 2 --spp 3 --guide-rays -o " + (dir / "seq").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = runCli("denoise -b vulkan -m svgf --set variant=voorhuis --set taa=false -i " + (dir / "seq").string() + " -o " +
             (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  auto reader = SequenceReader::open(dir / "seq");
  auto d = vulkanDevice()->createDenoiser("svgf");
  d->set("variant", "voorhuis");
  d->set("taa", "false");
  GuideRays gr;
  for (int i = 0; i < frames; ++i) {
    const Frame f = reader->read(i);
    const Image api = gr.denoise(*d, f, reader->readGuideRaySamples(i));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", f.number);
    const Image cli = readRgbExr(dir / "out" / name);
    ASSERT_EQ(cli.width * cli.height, w * h);
    EXPECT_EQ(cli.pixels, api.pixels) << "frame " << i;
  }
  std::ifstream in(dir / "out" / "timings.json");
  const auto timings = nlohmann::json::parse(in);
  EXPECT_EQ(timings["guideRays"]["samplesPerPixel"], spp);
  EXPECT_TRUE(timings["frames"][0]["passes"].contains("guideRays.premix"));
  EXPECT_TRUE(timings["frames"][0]["passes"].contains("guideRays.resolve"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtd::test
#endif
