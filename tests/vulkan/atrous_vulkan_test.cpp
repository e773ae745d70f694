// The a-trous passes on Vulkan against the CPU's (src/passes/atrous.h): the guide's depth
// gradient, single levels with steps 1 and 2 (shared-memory tiles) and 4 (direct loads), both
// kernels, with and without variance propagation, and the clamped 3x3 Gaussian.
#if __has_include("passes/atrous.h")
#include <cstring>

#include "backend/vulkan/context.h"
#include "backend/vulkan/passes.h"
#include "core/frame_data.h"
#include "passes/atrous.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

struct Fixture {
  vk::Context ctx{DeviceDesc{.backend = Backend::Vulkan}};
  FrameData cpu;
  vk::GpuFrame gpu;
  AtrousGuide guide;
  AtrousImage in;
  vk::Planes gradient, image;

  explicit Fixture(float maxDepthSlope = 0.0f) {
    const Frame f = syntheticFrames(1)[0];
    importFrame(f.inputs(), {Buffer::Color}, cpu);
    for (Buffer b : {Buffer::Depth, Buffer::Normal}) {
      gpu.present[int(b)] = true;
      upload(cpu.planes(b), gpu.planes[int(b)]);
    }
    gpu.width = kWidth;
    gpu.height = kHeight;
    guide.resize(kWidth, kHeight, 8);
    guide.build(cpu.plane(Buffer::Depth), cpu.planes(Buffer::Normal), nullptr, maxDepthSlope);
    gradient.allocate(ctx, kWidth, kHeight, 2);
    // Level input: the noisy colour, its luminance and a variance that varies over the image.
    in.resize(kWidth, kHeight, 8);
    std::vector<Plane> planes(5, Plane(kWidth, kHeight));
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const float r = cpu.plane(Buffer::Color, 0)(x, y), g = cpu.plane(Buffer::Color, 1)(x, y),
                    b = cpu.plane(Buffer::Color, 2)(x, y);
        const float l = luminance(r, g, b);
        const float v[5] = {r, g, b, l, 0.3f * l * l + 0.01f * float(x % 7)};
        for (int c = 0; c < 5; ++c) planes[size_t(c)](x, y) = v[c];
      }
    for (int c = 0; c < 3; ++c) in.color[c].copyFrom(planes[size_t(c)]);
    in.lum.copyFrom(planes[3]);
    in.var.copyFrom(planes[4]);
    upload(planes, image);
  }
  void upload(const std::vector<Plane>& planes, vk::Planes& out) {
    out.allocate(ctx, kWidth, kHeight, int(planes.size()));
    std::vector<float> all;
    for (const auto& p : planes) all.insert(all.end(), p.data.begin(), p.data.end());
    ctx.upload(out.buffer, all.data(), all.size() * 4);
  }
  std::vector<float> download(const vk::Planes& p) {
    std::vector<float> v(p.planeSize() * size_t(p.count));
    ctx.download(p.buffer, v.data(), v.size() * 4);
    return v;
  }
  template <class F> void run(F&& body) {
    vk::DescriptorCache cache(ctx);
    ctx.runOnce([&](VkCommandBuffer cmd) {
      vk::Recorder rec(ctx, cache, cmd, VK_NULL_HANDLE, 0);
      body(rec);
    });
  }
};

// Max |gpu - cpu| / max|cpu| over a plane.
double relError(const float* gpu, const PaddedPlane& cpu) {
  double err = 0, ref = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      err = std::max(err, double(std::abs(gpu[size_t(y) * kWidth + x] - cpu.at(x, y))));
      ref = std::max(ref, double(std::abs(cpu.at(x, y))));
    }
  return ref > 0 ? err / ref : err;
}

TEST(VulkanAtrous, GuideGradientMatchesCpu) {
  RTD_REQUIRE_VULKAN();
  for (float slope : {0.0f, 0.05f}) {
    Fixture fx(slope);
    fx.run([&](vk::Recorder& rec) { vk::atrousGuide(rec, fx.gpu, slope, fx.gradient); });
    const auto g = fx.download(fx.gradient);
    const size_t n = size_t(kWidth) * kHeight;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        ASSERT_EQ(g[size_t(y) * kWidth + x], fx.guide.gradX.at(x, y)) << x << "," << y;
        ASSERT_EQ(g[n + size_t(y) * kWidth + x], fx.guide.gradY.at(x, y)) << x << "," << y;
      }
  }
}

TEST(VulkanAtrous, LevelsMatchCpu) {
  RTD_REQUIRE_VULKAN();
  Fixture fx;
  vk::Planes out;
  out.allocate(fx.ctx, kWidth, kHeight, 5);
  for (AtrousKernel kernel : {AtrousKernel::B3Spline5x5, AtrousKernel::Binomial3x3})
    for (int step : {1, 2, 4})
      for (bool propagate : {true, false}) {
        AtrousLevel lv;
        lv.kernel = kernel;
        lv.step = step;
        lv.propagateVariance = propagate;
        lv.varianceScale = step == 2;
        AtrousImage cpuOut;
        cpuOut.resize(kWidth, kHeight, 8);
        cpuOut.var = fx.in.var;  // untouched without propagation
        atrousLevel(fx.guide, lv, fx.in, cpuOut);

        vk::GpuAtrousLevel g;
        g.radius = kernelRadius(kernel);
        g.step = step;
        g.propagateVariance = propagate;
        g.varianceScale = lv.varianceScale;
        fx.run([&](vk::Recorder& rec) {
          vk::atrousGuide(rec, fx.gpu, 0.0f, fx.gradient);
          vk::atrousLevel(rec, fx.gpu, fx.gradient, g, fx.image, out);
        });
        const auto o = fx.download(out);
        const size_t n = size_t(kWidth) * kHeight;
        const PaddedPlane* want[5] = {&cpuOut.color[0], &cpuOut.color[1], &cpuOut.color[2], &cpuOut.lum, &cpuOut.var};
        for (int p = 0; p < 5; ++p)
          EXPECT_LE(relError(o.data() + p * n, *want[p]), 1e-5)
              << "kernel " << int(kernel) << " step " << step << " propagate " << propagate << " plane " << p;
        // The filter must actually have smoothed: the output differs from the input.
        double change = 0;
        for (int y = 0; y < kHeight; ++y)
          for (int x = 0; x < kWidth; ++x) change = std::max(change, double(std::abs(o[size_t(y) * kWidth + x] - fx.in.color[0].at(x, y))));
        EXPECT_GT(change, 0.1);
      }
}

TEST(VulkanAtrous, Gaussian3x3MatchesCpu) {
  RTD_REQUIRE_VULKAN();
  Fixture fx;
  PaddedPlane cpuOut;
  cpuOut.resize(kWidth, kHeight, 8);
  gaussian3x3(fx.in.var, cpuOut);
  vk::Planes out;
  out.allocate(fx.ctx, kWidth, kHeight, 5);
  fx.run([&](vk::Recorder& rec) { vk::gaussian3x3(rec, fx.image, 4, out, 2); });
  const auto o = fx.download(out);
  EXPECT_LE(relError(o.data() + 2 * size_t(kWidth) * kHeight, cpuOut), 1e-6);
}

}  // namespace
}  // namespace rtd::test
#endif
