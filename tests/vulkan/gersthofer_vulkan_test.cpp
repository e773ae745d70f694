// Gersthofer's pipeline on Vulkan against the CPU (lavapipe in CI): the composite mode with
// every input it reads (indirect diffuse, indirect ray length, roughness and metalness, sample
// masks with the 1/c boost, the hidden area), the FXAA and eye-reprojection passes alone, and
// the two-view denoiser.
#if __has_include("rtd/methods/svgf.h")
#include <algorithm>
#include <cmath>
#include <map>

#include "backend/vulkan/context.h"
#include "backend/vulkan/passes.h"
#include "core/frame_data.h"
#include "passes/eye_reprojection.h"
#include "passes/fxaa.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// Synthetic frames with Gersthofer's inputs: indirect diffuse 40 % of the colour, an indirect
// ray length, metal on the right half; frame 1 with an all-ones sample mask, frames 2-3 traced
// at a quarter of the pixels (the others black); a hidden border of 4 pixels.
std::vector<Frame> gersthoferFrames(int count) {
  auto seq = syntheticFrames(count);
  for (size_t k = 0; k < seq.size(); ++k) {
    Frame& f = seq[k];
    f[Buffer::IndirectDiffuse] = f[Buffer::Color];
    for (auto& v : f[Buffer::IndirectDiffuse].pixels) v *= 0.4f;
    f[Buffer::SecondaryDistance] = Image(f.width, f.height, 1);
    f[Buffer::Metalness] = Image(f.width, f.height, 1);
    f[Buffer::HiddenArea] = Image(f.width, f.height, 1);
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        f[Buffer::SecondaryDistance].at(x, y) = 0.5f + 0.1f * float((x * 7 + y * 3 + int(k)) % 11);
        f[Buffer::Metalness].at(x, y) = x > f.width / 2 ? 1.0f : 0.0f;
        f[Buffer::HiddenArea].at(x, y) = x < 4 || y < 4 || x >= f.width - 4 || y >= f.height - 4 ? 1.0f : 0.0f;
      }
    if (k == 1) f[Buffer::SampleMask] = Image(f.width, f.height, 1, 1.0f);  // fully traced: no masking
    if (k == 2 || k == 3) {
      f[Buffer::SampleMask] = Image(f.width, f.height, 1);
      for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
          const bool traced = (x + 2 * y + int(k)) % 4 == 0;
          f[Buffer::SampleMask].at(x, y) = traced ? 1.0f : 0.0f;
          if (!traced)
            for (Buffer b : {Buffer::Color, Buffer::IndirectDiffuse})
              for (int c = 0; c < 3; ++c) f[b].at(x, y, c) = 0.0f;
        }
    }
  }
  return seq;
}

void compareComposite(const std::vector<std::string>& settings, bool decisions, const std::string& what) {
  auto cpu = Device::create({.backend = Backend::Cpu, .threads = 1})->createDenoiser("svgf");
  auto gpu = vulkanDevice()->createDenoiser("svgf");
  for (auto* d : {cpu.get(), gpu.get()}) {
    d->set("variant", "gersthofer");
    for (const auto& s : settings) {
      const auto eq = s.find('=');
      d->set(s.substr(0, eq), s.substr(eq + 1));
    }
  }
  const auto seq = gersthoferFrames(5);
  for (size_t i = 0; i < seq.size(); ++i) {
    const Frame& f = seq[i];
    Image a(f.width, f.height, 3), b(f.width, f.height, 3);
    cpu->denoise(f.inputs(), a.view());
    gpu->denoise(f.inputs(), b.view());
    const std::string label = what + ", frame " + std::to_string(i);
    if (decisions) expectCloseExceptFlips(b, a, kSvgfMaxRel, kSvgfMeanRel, 0.01, label);  // FXAA decisions (svgf_vulkan_test.cpp)
    else expectClose(b, a, kSvgfMaxRel, kSvgfMeanRel, label);
    EXPECT_EQ(b.at(1, 1, 0), 0.0f) << "hidden area";
  }
}

TEST(VulkanGersthofer, CompositePipelineMatchesCpu) {
  RTD_REQUIRE_VULKAN();
  compareComposite({"fxaa=false"}, false, "composite");
  compareComposite({"fxaa=false", "maskCoverage=0.5", "taa=true"}, false, "fixed coverage, TAA");
  compareComposite({"toneMap=aces"}, true, "FXAA and ACES");
}

TEST(VulkanGersthofer, FxaaPassMatchesCpu) {
  RTD_REQUIRE_VULKAN();
  vk::Context ctx{DeviceDesc{.backend = Backend::Vulkan}};
  const int w = kWidth, h = kHeight;
  Plane3 in, out;
  resize(in, w, h);
  resize(out, w, h);
  Plane luma(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // A disc and a shallow line, hard-edged, on a gradient: edges in every direction.
      const float dx = x - 30.5f, dy = y - 20.5f;
      const float v = (dx * dx + dy * dy < 150.0f ? 2.0f : 0.1f) + (y >= 5 + x / 5 ? 0.8f : 0.0f) + 0.01f * x;
      in[0](x, y) = v;
      in[1](x, y) = 0.5f * v;
      in[2](x, y) = 0.2f + 0.1f * v;
    }
  fxaa(in, FxaaParams{}, luma, out);
  vk::Planes src, dst;
  src.allocate(ctx, w, h, 4);
  dst.allocate(ctx, w, h, 3);
  std::vector<float> all;
  for (const Plane* p : {&in[0], &in[1], &in[2], &luma}) all.insert(all.end(), p->data.begin(), p->data.end());
  ctx.upload(src.buffer, all.data(), all.size() * 4);
  vk::DescriptorCache cache(ctx);
  ctx.runOnce([&](VkCommandBuffer cmd) {
    vk::Recorder rec(ctx, cache, cmd, VK_NULL_HANDLE, 0);
    vk::fxaa(rec, src, dst);
  });
  std::vector<float> o(size_t(w) * h * 3);
  ctx.download(dst.buffer, o.data(), o.size() * 4);
  Image a(w, h, 3), b(w, h, 3);
  int changed = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        a.at(x, y, c) = out[c](x, y);
        b.at(x, y, c) = o[size_t(c) * w * h + size_t(y) * w + x];
        changed += c == 0 && out[0](x, y) != in[0](x, y);
      }
  EXPECT_GT(changed, 100);  // the test image has edges FXAA works on
  // The same input on both sides: the decisions match; the shifted bilinear samples to float rounding.
  expectClose(b, a, 1e-5, 1e-7, "fxaa");
}

// Eye reprojection of a plane seen by two parallel cameras, with an occluder in the source eye.
TEST(VulkanGersthofer, EyeReprojectionPassMatchesCpu) {
  RTD_REQUIRE_VULKAN();
  vk::Context ctx{DeviceDesc{.backend = Backend::Vulkan}};
  const int w = kWidth, h = kHeight;
  const float fovY = 1.0f, aspect = float(w) / float(h), focal = 1.0f / std::tan(0.5f * fovY);
  auto frame = [&](float ex, bool occluder) {
    Frame f;
    f.width = w;
    f.height = h;
    f.camera.worldToCamera = {1, 0, 0, -ex, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const float n = 0.01f, fa = 1000.0f;
    f.camera.projection = {focal / aspect, 0, 0, 0, 0, focal, 0, 0, 0, 0, (n + fa) / (n - fa), 2 * n * fa / (n - fa), 0, 0, -1, 0};
    f.camera.valid = true;
    for (Buffer b : {Buffer::Color, Buffer::Position, Buffer::Normal}) f[b] = Image(w, h, 3);
    f[Buffer::Depth] = Image(w, h, 1);
    f[Buffer::ObjectId] = Image(w, h, 1, 1.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float ndx = (x + 0.5f) / w * 2 - 1, ndy = 1 - (y + 0.5f) / h * 2;
        const bool occ = occluder && x >= 20 && x < 30;
        const float z = occ ? 1.0f : 2.0f + 0.01f * y;
        f[Buffer::Position].at(x, y, 0) = ex + ndx * z * aspect / focal;
        f[Buffer::Position].at(x, y, 1) = ndy * z / focal;
        f[Buffer::Position].at(x, y, 2) = -z;
        f[Buffer::Normal].at(x, y, 2) = 1.0f;
        f[Buffer::Depth].at(x, y) = z;
        if (occ) f[Buffer::ObjectId].at(x, y) = 2.0f;
        for (int c = 0; c < 3; ++c) f[Buffer::Color].at(x, y, c) = 0.1f * (x % 9) + 0.3f * c + 0.05f * (y % 5);
      }
    return f;
  };
  const Frame target = frame(-0.05f, false), source = frame(0.05f, true);
  FrameData ct, cs;
  importFrame(target.inputs(), {Buffer::Color}, ct);
  importFrame(source.inputs(), {Buffer::Color}, cs);
  const ReprojectionSettings s;
  Plane3 tl, sl, out;
  for (int c = 0; c < 3; ++c) {
    tl[c] = ct.plane(Buffer::Color, c);
    sl[c] = cs.plane(Buffer::Color, c);
    out[c].resize(w, h);
  }
  for (auto& v : sl[0].data) v *= 3.0f;  // the two eyes' light differ
  Plane moved(w, h);
  const size_t n = eyeReproject(EyeGuide::of(ct), EyeGuide::of(cs), s, 0.5f, tl, sl, out, &moved);
  EXPECT_GT(n, size_t(w * h / 2));
  EXPECT_LT(n, size_t(w * h - 5 * h));  // the occluder and the border reject some

  auto upload = [&](const std::vector<const Plane*>& planes, vk::Planes& dst) {
    dst.allocate(ctx, w, h, int(planes.size()));
    std::vector<float> all;
    for (const Plane* p : planes) all.insert(all.end(), p->data.begin(), p->data.end());
    ctx.upload(dst.buffer, all.data(), all.size() * 4);
  };
  auto gpuFrame = [&](const FrameData& d, vk::GpuFrame& g) {
    g.width = w;
    g.height = h;
    for (Buffer b : {Buffer::Position, Buffer::Normal, Buffer::Depth, Buffer::ObjectId}) {
      std::vector<const Plane*> ps;
      for (const auto& p : d.planes(b)) ps.push_back(&p);
      upload(ps, g.planes[int(b)]);
      g.present[int(b)] = true;
    }
    g.camera = vk::DeviceBuffer(ctx, 32 * sizeof(float), false);
    float m[32];
    std::copy(d.camera.worldToCamera.begin(), d.camera.worldToCamera.end(), m);
    std::copy(d.camera.projection.begin(), d.camera.projection.end(), m + 16);
    ctx.upload(g.camera, m, sizeof m);
    g.cameraValue = d.camera;
  };
  vk::GpuFrame gt, gs;
  gpuFrame(ct, gt);
  gpuFrame(cs, gs);
  vk::Planes gtl, gsl, gout;
  upload({&tl[0], &tl[1], &tl[2]}, gtl);
  upload({&sl[0], &sl[1], &sl[2]}, gsl);
  gout.allocate(ctx, w, h, 3);
  vk::DescriptorCache cache(ctx);
  ctx.runOnce([&](VkCommandBuffer cmd) {
    vk::Recorder rec(ctx, cache, cmd, VK_NULL_HANDLE, 0);
    vk::eyeReproject(rec, gt, gs, nullptr, 0, s, 0.5f, gtl, gsl, gout);
  });
  std::vector<float> o(size_t(w) * h * 3);
  ctx.download(gout.buffer, o.data(), o.size() * 4);
  Image a(w, h, 3), b(w, h, 3);
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < w * h; ++i) {
      a.pixels[size_t(i) * 3 + c] = out[c].data[i];
      b.pixels[size_t(i) * 3 + c] = o[size_t(c) * w * h + i];
    }
  expectClose(b, a, 1e-5, 1e-7, "eye reprojection");
}

// Both eyes in one command buffer with the exchange between them, against the CPU's two-view
// denoiser: the right eye is the left eye's view from 0.1 to the right (the synthetic scene's
// camera moving right by 0.02 per frame: frame k + 5), so the eyes overlap and differ.
TEST(VulkanGersthofer, StereoMatchesCpuWithAndWithoutEyeReprojection) {
  RTD_REQUIRE_VULKAN();
  const auto frames = gersthoferFrames(8);
  for (bool share : {true, false}) {
    SvgfSettings s = SvgfSettings::forVariant(SvgfVariant::gersthofer);
    s.fxaa = false;
    s.eyeReprojection = share;
    auto cpu = Device::create({.backend = Backend::Cpu, .threads = 1})->createStereoDenoiser(s);
    auto gpu = vulkanDevice()->createStereoDenoiser(s);
    for (int i = 0; i < 3; ++i) {
      StereoFrameInputs in;
      in.eye[0] = frames[size_t(i)].inputs();
      in.eye[1] = frames[size_t(i + 5)].inputs();
      Image a0(kWidth, kHeight, 3), a1 = a0, b0 = a0, b1 = a0;
      cpu->denoise(in, a0.view(), a1.view());
      gpu->denoise(in, b0.view(), b1.view());
      const std::string what = std::string(share ? "shared" : "apart") + ", frame " + std::to_string(i);
      expectClose(b0, a0, kSvgfMaxRel, kSvgfMeanRel, "left, " + what);
      expectClose(b1, a1, kSvgfMaxRel, kSvgfMeanRel, "right, " + what);
    }
    const auto names = [&] {
      std::vector<std::string> n;
      for (const auto& p : gpu->stats().passes) n.push_back(p.name);
      return n;
    }();
    EXPECT_EQ(std::count(names.begin(), names.end(), "eyeReprojection"), share ? 1 : 0);
    EXPECT_EQ(std::count(names.begin(), names.end(), "(other eye)"), 0);
  }
}

// Gersthofer's memory categories (his Table 5.4) on Vulkan as on the CPU: per eye the composite
// and indirect diffuse accumulators (2 x 6 planes each, double-buffered) and the indirect ray
// length (2 planes), 26 float planes, TAA off in the preset; the frames and the rest besides.
TEST(VulkanGersthofer, StereoMemoryReportHasHisCategories) {
  RTD_REQUIRE_VULKAN();
  const auto frames = gersthoferFrames(6);
  auto gpu = vulkanDevice()->createStereoDenoiser(SvgfSettings::forVariant(SvgfVariant::gersthofer));
  StereoFrameInputs in;
  in.eye[0] = frames[0].inputs();
  in.eye[1] = frames[5].inputs();
  Image l(kWidth, kHeight, 3), r = l;
  gpu->denoise(in, l.view(), r.view());
  std::map<std::string, uint64_t> m;
  for (const MemoryUse& u : gpu->stats().memory) m[u.category] += u.bytes;
  const uint64_t px = uint64_t(kWidth) * kHeight;
  EXPECT_EQ(m["history"], 2 * 26 * 4 * px);
  EXPECT_GT(m["intermediate"], 2 * 30 * 4 * px);
  EXPECT_GT(m["frames"], 2 * 10 * 4 * px);
  EXPECT_GT(m["staging"], 0u);
}

}  // namespace
}  // namespace rtd::test
#endif
