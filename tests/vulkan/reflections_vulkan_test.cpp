// SVGF's Voorhuis mode on Vulkan against the CPU: the surface classes, the specular
// reprojection (diamond search), the clipping box, and the whole method over a rendered
// sequence with mirrors and glossy metals (with guide-ray supersampling: guide_rays_vulkan_test.cpp).
#if __has_include("rtd/methods/svgf.h") && defined(HAVE_RTDENOISE_RENDER)
#include <bit>

#include "backend/vulkan/context.h"
#include "backend/vulkan/passes.h"
#include "core/frame_data.h"
#include "methods/svgf/svgf_reflections_vulkan.h"
#include "passes/neighbourhood_clipping.h"
#include "rtd/render/render.h"
#include "download_planes.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

// Two consecutive frames of the built-in glossy scene (mirrors, gold spheres of roughness
// 0.05-0.55, a glossy floor) at a size that is not a multiple of 16.
struct Rendered {
  Frame frames[6];
  Rendered() {
    render::RenderSettings rs;
    rs.width = kWidth;
    rs.height = kHeight;
    render::Renderer r(render::Scene::load("glossy"), rs);
    for (int i = 0; i < 6; ++i) frames[i] = r.render(20 + i);
  }
};
const Rendered& reflectionFrames() {
  static const Rendered r;
  return r;
}

// Uploads every buffer of a CPU frame into a GpuFrame (planes as the import pass leaves them).
void upload(vk::Context& ctx, const FrameData& f, vk::GpuFrame& g) {
  g.width = f.width;
  g.height = f.height;
  for (int b = 0; b < kBufferCount; ++b) {
    g.present[b] = f.has(Buffer(b));
    if (!g.present[b]) continue;
    const auto& planes = f.buffers[b];
    g.planes[b].allocate(ctx, f.width, f.height, int(planes.size()));
    std::vector<float> all;
    for (const Plane& p : planes) all.insert(all.end(), p.data.begin(), p.data.end());
    ctx.upload(g.planes[b].buffer, all.data(), all.size() * 4);
  }
  g.cameraValue = f.camera;
  g.camera = vk::DeviceBuffer(ctx, 32 * sizeof(float), false);
  float cam[32];
  std::copy(f.camera.worldToCamera.begin(), f.camera.worldToCamera.end(), cam);
  std::copy(f.camera.projection.begin(), f.camera.projection.end(), cam + 16);
  ctx.upload(g.camera, cam, sizeof cam);
}

template <class F> void record(vk::Context& ctx, F&& body) {
  vk::DescriptorCache cache(ctx);
  ctx.runOnce([&](VkCommandBuffer cmd) {
    vk::Recorder rec(ctx, cache, cmd, VK_NULL_HANDLE, 0);
    body(rec);
  });
}

TEST(VulkanReflections, ClassesAndSpecularReprojectionMatchCpu) {
  RTD_REQUIRE_VULKAN();
  vk::Context ctx{DeviceDesc{.backend = Backend::Vulkan}};
  const Rendered& r = reflectionFrames();
  FrameData prev, cur;
  importFrame(r.frames[0].inputs(), {Buffer::Color}, prev);
  importFrame(r.frames[1].inputs(), {Buffer::Color}, cur);
  const int w = cur.width, h = cur.height;
  const size_t n = size_t(w) * h;

  // CPU: classes of both frames, primary and specular reprojection.
  PixelVector<uint8_t> cls, prevCls;
  classifySurfaces(cur, {}, false, cls);
  classifySurfaces(prev, {}, false, prevCls);
  // Both subpixel fits (SvgfSettings::subpixelFit).
  for (SvgfSubpixelFit fit : {SvgfSubpixelFit::inverseDistance, SvgfSubpixelFit::quadratic}) {
  SCOPED_TRACE(fit == SvgfSubpixelFit::quadratic ? "quadratic" : "Eqs. 2-3");
  Reprojection primary, specular;
  reproject(cur, &prev, ReprojectionSettings{}, primary);
  ReflectionMotionStats st;
  ReflectionMotionOptions opt;
  opt.search.fit = fit == SvgfSubpixelFit::quadratic ? SubpixelFit::quadratic : SubpixelFit::inverseDistance;
  specularReprojection(cur, &prev, cls, prevCls, primary, SpecularMotion::Reflection, opt, specular, &st);
  ASSERT_GT(st.mirrorPixels, 100u);
  ASSERT_GT(st.glossyPixels, 100u);

  // GPU: the same two frames through svgf::GpuReflections.
  vk::GpuFrame gPrev, gCur;
  upload(ctx, prev, gPrev);
  upload(ctx, cur, gCur);
  vk::Planes rp;
  rp.allocate(ctx, w, h, 8);
  svgf::GpuReflections refl;
  refl.resize(ctx, w, h);
  SvgfSettings s = SvgfSettings::forVariant(SvgfVariant::voorhuis);
  s.preferLobes = false;
  s.subpixelFit = fit;
  const auto parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return cur.has(b); }, false);
  record(ctx, [&](vk::Recorder& rec) {
    vk::reproject(rec, gPrev, nullptr, ReprojectionSettings{}, rp);
    refl.prepare(rec, gPrev, nullptr, s, parts, false, rp);  // frame 0: classes only
  });
  std::vector<float> gpuPrevCls = download(ctx, refl.classes());
  record(ctx, [&](vk::Recorder& rec) {
    vk::reproject(rec, gCur, &gPrev, ReprojectionSettings{}, rp);
    refl.prepare(rec, gCur, &gPrev, s, parts, false, rp);
  });
  const std::vector<float> gpuCls = download(ctx, refl.classes());
  for (size_t i = 0; i < n; ++i) {
    ASSERT_EQ(gpuCls[i], float(cls[i])) << i;
    ASSERT_EQ(gpuPrevCls[i], float(prevCls[i])) << i;
  }
  std::vector<uint32_t> g(n * 8);
  ctx.download(refl.specularReprojection().buffer, g.data(), g.size() * 4);
  // Searched pixels: the same record, or (a float tie in the search broken the other way) a
  // match within a pixel. Measured on lavapipe: every searched pixel identical.
  size_t searched = 0, same = 0, near = 0;
  for (size_t i = 0; i < n; ++i) {
    const SurfaceClass c = SurfaceClass(cls[i]);
    const float gx = std::bit_cast<float>(g[6 * n + i]), gy = std::bit_cast<float>(g[7 * n + i]);
    const float cx = specular.prevX.data[i], cy = specular.prevY.data[i];
    if (c != SurfaceClass::Mirror && c != SurfaceClass::GlossyReflection) {
      EXPECT_EQ(g[i] & 3u, uint32_t(specular.kind[i])) << i;  // the primary record
      EXPECT_EQ(gx, cx);
      continue;
    }
    ++searched;
    const bool kindSame = (g[i] & 3u) == uint32_t(specular.kind[i]);
    if (kindSame && std::abs(gx - cx) <= 1e-4f && std::abs(gy - cy) <= 1e-4f) ++same;
    else if (std::hypot(gx - cx, gy - cy) <= 1.0f) ++near;
  }
  EXPECT_GE(double(same), 0.995 * searched) << same << " of " << searched << ", " << near << " within 1 px";
  EXPECT_EQ(same + near, searched);
  }
}

TEST(VulkanReflections, ClipBoxMatchesCpu) {
  RTD_REQUIRE_VULKAN();
  vk::Context ctx{DeviceDesc{.backend = Backend::Vulkan}};
  const Rendered& r = reflectionFrames();
  FrameData f;
  importFrame(r.frames[2].inputs(), {Buffer::Color}, f);
  const int w = f.width, h = f.height;
  const size_t n = size_t(w) * h;
  Plane3 color;
  for (int c = 0; c < 3; ++c) color[c] = f.plane(Buffer::Color, c);
  PixelVector<uint8_t> cls;
  classifySurfaces(f, {}, false, cls);
  PixelVector<uint8_t> mask(n);
  for (size_t i = 0; i < n; ++i) mask[i] = cls[i] != 0;
  PixelVector<uint32_t> key;
  surfaceKeys(f, cls, key);
  // Both neighbourhoods: every pixel of the window, and the pixel's own surface (class and
  // object id; clipOwnSurface, the default).
  for (bool own : {false, true}) {
  SCOPED_TRACE(own ? "own surface" : "whole window");
  Plane3 lo, hi, scratch;
  clipBox(color, &mask, ClipBoxOptions{}, lo, hi, scratch, own ? &key : nullptr);

  vk::GpuFrame g;
  upload(ctx, f, g);
  svgf::GpuReflections refl;
  refl.resize(ctx, w, h);
  SvgfSettings s = SvgfSettings::forVariant(SvgfVariant::voorhuis);
  s.clipOwnSurface = own;
  const auto parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return f.has(b); }, false);
  vk::Planes rp;
  rp.allocate(ctx, w, h, 8);
  const vk::Planes* box = nullptr;
  record(ctx, [&](vk::Recorder& rec) {
    vk::reproject(rec, g, nullptr, ReprojectionSettings{}, rp);
    refl.prepare(rec, g, nullptr, s, parts, false, rp);
    box = refl.clipBox(rec, g[Buffer::Color], svgf::StreamPlan{Buffer::Color, "color", true, false}, s);
  });
  ASSERT_NE(box, nullptr);
  const std::vector<float> b = download(ctx, *box);
  double maxErr = 0, maxRef = 0;
  size_t open = 0;
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < n; ++i) {
      if (!mask[i]) {
        EXPECT_TRUE(std::isinf(b[c * n + i]) && b[c * n + i] < 0);
        EXPECT_TRUE(std::isinf(b[(3 + c) * n + i]) && b[(3 + c) * n + i] > 0);
        ++open;
        continue;
      }
      maxErr = std::max({maxErr, double(std::abs(b[c * n + i] - lo[c].data[i])), double(std::abs(b[(3 + c) * n + i] - hi[c].data[i]))});
      maxRef = std::max(maxRef, double(std::abs(hi[c].data[i])));
    }
  EXPECT_GT(open, 0u);
  EXPECT_LE(maxErr, 1e-6 * maxRef) << "max " << maxErr << " of " << maxRef;  // same sums, same order
  }
}

// The whole method: Ours (lobes, reflection motion, reflected features, Eq. 6, clipping, per-
// class alpha) and NoSpecReproj over six rendered frames; Ours also with the Catmull-Rom TAA
// history, which reads the accepted taps of the record TAA follows (voorhuis_taa_motion).
TEST(VulkanReflections, VoorhuisMatchesCpuOnARenderedSequence) {
  RTD_REQUIRE_VULKAN();
  const Rendered& r = reflectionFrames();
  for (const char* variant : {"voorhuis", "voorhuisNoSpecReproj", "voorhuis+catmullRom", "voorhuis+noMirrorTaa"}) {
    auto cpuDevice = Device::create({.backend = Backend::Cpu, .threads = 1});
    auto cpu = cpuDevice->createDenoiser("svgf");
    auto gpu = vulkanDevice()->createDenoiser("svgf");
    const bool catmullRom = std::string(variant) == "voorhuis+catmullRom";
    const bool noMirrorTaa = std::string(variant) == "voorhuis+noMirrorTaa";
    for (Denoiser* d : {cpu.get(), gpu.get()}) {
      d->set("variant", catmullRom || noMirrorTaa ? "voorhuis" : variant);
      if (catmullRom) d->set("taaHistoryFilter", "catmullRom");
      if (noMirrorTaa) d->set("taaMirrorHistory", "none");
    }
    for (int i = 0; i < 6; ++i) {
      const Frame& f = r.frames[i];
      Image a(f.width, f.height, 3), b(f.width, f.height, 3);
      cpu->denoise(f.inputs(), a.view());
      gpu->denoise(f.inputs(), b.view());
      EXPECT_EQ(cpu->stats().notes, gpu->stats().notes);
      // As svgf_vulkan_test.cpp (the filter's exp and division differ by ~1e-6 relative);
      // the max allows a handful of pixels whose search broke a float tie the other way.
      const ErrorStats e = compare(b, a);
      for (int c = 0; c < 3; ++c) {
        EXPECT_LE(e.meanAbs[c], 2e-5 * e.maxRef) << variant << " frame " << i << ": " << describe(e);
        EXPECT_LE(e.maxAbs[c], 2e-2 * e.maxRef) << variant << " frame " << i << ": " << describe(e);
      }
    }
  }
}

// A denoiser that ran three frames as `before` and was then switched to `after` and reset runs
// the next three frames as a fresh `after` denoiser ("" is plain SVGF).
void expectSwitchedRunsAsFresh(const char* before, const char* after) {
  const Rendered& r = reflectionFrames();
  auto switched = vulkanDevice()->createDenoiser("svgf");
  auto fresh = vulkanDevice()->createDenoiser("svgf");
  if (*before) switched->set("variant", before);
  fresh->set("variant", after);
  Image a(r.frames[0].width, r.frames[0].height, 3), b(a.width, a.height, 3);
  for (int i = 0; i < 3; ++i) switched->denoise(r.frames[i].inputs(), a.view());
  switched->set("variant", after);
  switched->reset();
  for (int i = 3; i < 6; ++i) {
    switched->denoise(r.frames[i].inputs(), a.view());
    fresh->denoise(r.frames[i].inputs(), b.view());
    const ErrorStats e = compare(a, b);
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(e.maxAbs[c], 1e-6 * e.maxRef) << before << " -> " << after << ", frame " << i << ": " << describe(e);
  }
}

// As VoorhuisParts.SwitchingThePartsOffLeavesNoneOfTheirStateBehind on the CPU: after a switch
// to a preset without the parts, the GPU denoiser runs as one that never had them.
TEST(VulkanReflections, SwitchingThePartsOffLeavesNoneOfTheirStateBehind) {
  RTD_REQUIRE_VULKAN();
  expectSwitchedRunsAsFresh("voorhuis", "voorhuisBase");
}

// The parts' device planes are allocated when the parts first run (GpuReflections::resize): a
// denoiser that ran plain SVGF before it switched to voorhuis runs as one that had the parts
// from the start.
TEST(VulkanReflections, SwitchingThePartsOnRunsAsADenoiserThatHadThem) {
  RTD_REQUIRE_VULKAN();
  expectSwitchedRunsAsFresh("", "voorhuis");
}

}  // namespace
}  // namespace rtd::test
#endif
