// Guide-ray supersampling through files and the CLI (docs/sequence-format.md, "Guide-ray
// samples"): `rtdenoise render --guide-rays` then `rtdenoise denoise` gives, bit for bit, what the
// API path gives (Renderer::render with samples, GuideRays::premix, the denoiser, resolve).
#ifdef HAVE_RTDENOISE_RENDER
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "render/render_test_util.h"
#include "rtd/guide_rays.h"
#include "rtd/rtd.h"
#include "support/run_cli.h"

namespace rtd::render::test {
namespace {

namespace fs = std::filesystem;

std::string frameName(int n) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.exr", n);
  return name;
}

TEST(GuideRayCli, RenderedSamplesThroughTheCliEqualTheApiPath) {
  const int w = 24, h = 16, frames = 3, spp = 3;
  const fs::path dir = tempDir("guide_cli");
  const std::string size = std::to_string(w) + "x" + std::to_string(h);
  auto r = rtd::test::runCli("render --scene corridorglossy --size " + size + " --frames " + std::to_string(frames) +
                             " --spp " + std::to_string(spp) + " --guide-rays -o " + (dir / "seq").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string settings = " -m svgf --set variant=voorhuis --set taa=false -i " + (dir / "seq").string();
  r = rtd::test::runCli("denoise" + settings + " -o " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("3 spp with guide rays"), std::string::npos) << r.output;
  r = rtd::test::runCli("denoise" + settings + " --no-guide-rays -o " + (dir / "guides").string());
  ASSERT_EQ(r.code, 0) << r.output;

  // The API path, independent of the files.
  auto scene = Scene::load("corridorglossy");
  RenderSettings rs = scene->suggestedSettings();
  rs.width = w;
  rs.height = h;
  rs.spp = spp;
  rs.guideRays = true;
  Renderer renderer(scene, rs);
  auto device = Device::create();
  auto withSamples = device->createDenoiser("svgf"), guidesOnly = device->createDenoiser("svgf");
  for (auto* d : {withSamples.get(), guidesOnly.get()}) {
    d->set("variant", "voorhuis");
    d->set("taa", "false");
  }
  auto reader = SequenceReader::open(dir / "seq");
  ASSERT_EQ(reader->guideRaySampleCount(), spp - 1);
  Image out(w, h, 3);
  double differs = 0;
  for (int i = 0; i < frames; ++i) {
    GuideRaySamples samples;
    const Frame f = renderer.render(i, Eye::Center, samples);
    // The files hold the render exactly.
    const GuideRaySamples read = reader->readGuideRaySamples(i);
    ASSERT_EQ(read.samples.size(), samples.samples.size());
    for (size_t k = 0; k < samples.samples.size(); ++k) {
      ASSERT_EQ(read.offsets[k].pixels, samples.offsets[k].pixels);
      for (int b = 0; b < kBufferCount; ++b) {
        ASSERT_EQ(read.samples[k].has(Buffer(b)), samples.samples[k].has(Buffer(b))) << bufferName(Buffer(b));
        if (samples.samples[k].has(Buffer(b))) {
          ASSERT_EQ(read.samples[k][Buffer(b)].pixels, samples.samples[k][Buffer(b)].pixels) << bufferName(Buffer(b));
        }
      }
    }
    GuideRays gr;
    const Frame mixed = gr.premix(f, samples);
    withSamples->denoise(mixed.inputs(), out.view());
    const Image api = gr.resolve(out);
    const Image cli = readRgbExr(dir / "out" / frameName(f.number));
    EXPECT_EQ(cli.pixels, api.pixels) << "frame " << f.number;
    guidesOnly->denoise(f.inputs(), out.view());
    const Image cliGuides = readRgbExr(dir / "guides" / frameName(f.number));
    EXPECT_EQ(cliGuides.pixels, out.pixels) << "frame " << f.number;
    for (size_t p = 0; p < api.pixels.size(); ++p) differs += std::abs(api.pixels[p] - out.pixels[p]);
  }
  EXPECT_GT(differs, 0.0);  // the samples did change the result

  std::ifstream in(dir / "out" / "timings.json");
  const auto timings = nlohmann::json::parse(in);
  EXPECT_EQ(timings["guideRays"]["samplesPerPixel"], spp);
  EXPECT_TRUE(timings["frames"][0]["passes"].contains("guideRays.premix"));
  fs::remove_all(dir);
}

TEST(GuideRayCli, UsageErrors) {
  const fs::path dir = tempDir("guide_cli_usage");
  auto r = rtd::test::runCli("render --scene corridorglossy --size 8x8 --frames 1 --guide-rays -o " + (dir / "a").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--spp 2"), std::string::npos) << r.output;
  r = rtd::test::runCli("render --scene corridorglossy --size 8x8 --frames 1 --spp 2 --guide-rays --stereo -o " +
                        (dir / "b").string());
  EXPECT_EQ(r.code, 2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtd::render::test
#endif
