// SVGF's variance pass on Vulkan (shaders/svgf_variance.comp) against svgf::estimateVariance and
// svgf::luminanceSigmaScale, with temporal, spatial (current luminance and Voorhuis' moments)
// and 3x3 / 7x7 windows, on 67x41.
#if __has_include("methods/svgf/svgf_passes.h")
#include "backend/vulkan/context.h"
#include "backend/vulkan/passes.h"
#include "core/frame_data.h"
#include "methods/svgf/svgf_passes.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

TEST(VulkanSvgfPasses, VarianceMatchesCpu) {
  RTD_REQUIRE_VULKAN();
  vk::Context ctx{DeviceDesc{.backend = Backend::Vulkan}};
  const Frame f = syntheticFrames(1)[0];
  FrameData cpu;
  importFrame(f.inputs(), {Buffer::Color}, cpu);
  const int w = kWidth, h = kHeight;
  const size_t n = size_t(w) * h;

  // Accumulated state: colour, moments and a history length that is short (< 4) in some places.
  Plane3 acc, cur;
  Plane m1(w, h), m2(w, h), len(w, h);
  resize(acc, w, h);
  resize(cur, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        cur[c](x, y) = cpu.plane(Buffer::Color, c)(x, y);
        acc[c](x, y) = 0.5f * cur[c](x, y) + 0.2f;
      }
      const float l = luminance(acc[0](x, y), acc[1](x, y), acc[2](x, y));
      m1(x, y) = l;
      m2(x, y) = l * l * (1.2f + 0.1f * float(y % 3));
      len(x, y) = float(1 + (x + 2 * y) % 7);
    }
  AtrousGuide guide;
  guide.resize(w, h, 8);
  guide.build(cpu.plane(Buffer::Depth), cpu.planes(Buffer::Normal), nullptr, 0.0f);

  vk::GpuFrame g;
  g.width = w;
  g.height = h;
  auto upload = [&](const std::vector<const Plane*>& planes, vk::Planes& out) {
    out.allocate(ctx, w, h, int(planes.size()));
    std::vector<float> all;
    for (const Plane* p : planes) all.insert(all.end(), p->data.begin(), p->data.end());
    ctx.upload(out.buffer, all.data(), all.size() * 4);
  };
  upload({&cpu.plane(Buffer::Depth)}, g.planes[int(Buffer::Depth)]);
  upload({&cpu.plane(Buffer::Normal, 0), &cpu.plane(Buffer::Normal, 1), &cpu.plane(Buffer::Normal, 2)},
         g.planes[int(Buffer::Normal)]);
  g.present[int(Buffer::Depth)] = g.present[int(Buffer::Normal)] = true;
  vk::Planes accGpu, curGpu, gradient, out, scale;
  upload({&acc[0], &acc[1], &acc[2], &m1, &m2, &len}, accGpu);
  upload({&cur[0], &cur[1], &cur[2]}, curGpu);
  gradient.allocate(ctx, w, h, 2);
  out.allocate(ctx, w, h, 5);
  scale.allocate(ctx, w, h, 1);

  struct Case {
    int radius;
    bool fromMoments, bandwidth, disable;
  };
  for (const Case& cs : {Case{3, false, false, false}, Case{1, true, true, false}, Case{3, false, false, true}}) {
    svgf::VarianceParams p;
    p.radius = cs.radius;
    p.fromMoments = cs.fromMoments;
    if (cs.disable) p.shortHistory = SvgfShortHistory::disableLuminanceWeight;
    if (cs.fromMoments) svgf::setDepthEpsilon(p, 0.0f, 2.5e-3f);  // the scale-free eps (svgf's default)
    AtrousImage cpuOut;
    cpuOut.resize(w, h, 8);
    PaddedPlane scratch[2];
    for (auto& sp : scratch) sp.resize(w, h, 8);
    const size_t spatial = svgf::estimateVariance(guide, {&len, &m1, &m2, &cur, &acc}, p, cpuOut, scratch);
    if (!cs.disable) { EXPECT_GT(spatial, n / 4) << "the spatial estimate must be exercised"; }
    SvgfSettings s;
    s.shortHistoryBandwidth = cs.bandwidth;
    s.shortHistory = p.shortHistory;
    PaddedPlane cpuScale;
    cpuScale.resize(w, h, 8);
    svgf::luminanceSigmaScale(len, s, cpuScale);

    struct PC {
      uint32_t width, height;
      float shortHistoryFrames;
      int32_t radius;
      float sigmaDepth, depthEpsilon;
      int32_t normalExponent;
      uint32_t luminanceMode, flags;
      float depthEpsilonRelative;
    } pc{uint32_t(w), uint32_t(h), 4.0f, cs.radius, p.sigmaDepth, p.depthEpsilon, p.normalExponent, 0,
         (cs.disable ? 4u : 1u) | (cs.fromMoments ? 2u : 0u) | (cs.bandwidth ? 8u : 0u), p.depthEpsilonRelative};
    vk::DescriptorCache cache(ctx);
    ctx.runOnce([&](VkCommandBuffer cmd) {
      vk::Recorder rec(ctx, cache, cmd, VK_NULL_HANDLE, 0);
      vk::atrousGuide(rec, g, 0.0f, gradient);
      rec.dispatch("svgf_variance",
                   {g[Buffer::Depth], g[Buffer::Normal], gradient, accGpu, curGpu, out, scale, vk::Binding(ctx.dummy())}, pc,
                   w, h);
    });
    std::vector<float> o(n * 5), k(n);
    ctx.download(out.buffer, o.data(), o.size() * 4);
    ctx.download(scale.buffer, k.data(), k.size() * 4);
    const PaddedPlane* want[5] = {&cpuOut.color[0], &cpuOut.color[1], &cpuOut.color[2], &cpuOut.lum, &cpuOut.var};
    for (int pl = 0; pl < 5; ++pl) {
      double err = 0, ref = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          err = std::max(err, double(std::abs(o[pl * n + size_t(y) * w + x] - want[pl]->at(x, y))));
          ref = std::max(ref, double(std::abs(want[pl]->at(x, y))));
        }
      // The CPU sums the window in double, the GPU in float: 1e-4 of the largest value.
      EXPECT_LE(err, 1e-4 * ref) << "radius " << cs.radius << " plane " << pl;
    }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) ASSERT_EQ(k[size_t(y) * w + x], cpuScale.at(x, y)) << x << "," << y;
  }
}

}  // namespace
}  // namespace rtd::test
#endif
