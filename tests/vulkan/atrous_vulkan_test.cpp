// The a-trous passes on Vulkan against the CPU's (src/passes/atrous.h): the guide's depth
// gradient, single levels with steps 1 and 2 (shared-memory tiles) and 4 (direct loads), both
// kernels, with and without variance propagation and surface keys, and the clamped 3x3 Gaussian.
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

// Mean |gpu - cpu| / max|cpu| over a plane.
double meanRelError(const float* gpu, const PaddedPlane& cpu) {
  double err = 0, ref = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      err += std::abs(gpu[size_t(y) * kWidth + x] - cpu.at(x, y));
      ref = std::max(ref, double(std::abs(cpu.at(x, y))));
    }
  err /= double(kWidth) * kHeight;
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
  vk::Planes out, gpuKey;
  out.allocate(fx.ctx, kWidth, kHeight, 5);
  // Surface keys (AtrousLevel::surfaceKey) in patches of 5 x 3 pixels, the two values alternating.
  PaddedPlane key;
  key.resize(kWidth, kHeight, 8);
  Plane keyPlane(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) key.at(x, y) = keyPlane(x, y) = float((x / 5 + y / 3) % 2);
  fx.upload({keyPlane}, gpuKey);
  for (bool keyed : {false, true})
  for (AtrousKernel kernel : {AtrousKernel::B3Spline5x5, AtrousKernel::Binomial3x3})
    for (int step : {1, 2, 4})
      for (bool propagate : {true, false})
      for (bool sharedTile : {true, false}) {  // the tiled shader and its untiled variant
        if (!sharedTile && step == 4) continue;  // step 4 is never tiled
        if (keyed && !propagate) continue;
        AtrousLevel lv;
        lv.surfaceKey = keyed ? &key : nullptr;
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
        g.sharedTile = sharedTile;
        g.surfaceKey = keyed ? &gpuKey : nullptr;
        fx.run([&](vk::Recorder& rec) {
          vk::atrousGuide(rec, fx.gpu, 0.0f, fx.gradient);
          vk::atrousLevel(rec, fx.gpu, fx.gradient, g, fx.image, out);
        });
        const auto o = fx.download(out);
        const size_t n = size_t(kWidth) * kHeight;
        const PaddedPlane* want[5] = {&cpuOut.color[0], &cpuOut.color[1], &cpuOut.color[2], &cpuOut.lum, &cpuOut.var};
        for (int p = 0; p < 5; ++p)
          EXPECT_LE(relError(o.data() + p * n, *want[p]), 1e-5) << "kernel " << int(kernel) << " step " << step
                                                                << " propagate " << propagate << " tile " << sharedTile
                                                                << " keyed " << keyed << " plane " << p;
        // The filter must actually have smoothed: the output differs from the input.
        double change = 0;
        for (int y = 0; y < kHeight; ++y)
          for (int x = 0; x < kWidth; ++x) change = std::max(change, double(std::abs(o[size_t(y) * kWidth + x] - fx.in.color[0].at(x, y))));
        EXPECT_GT(change, 0.1);
      }
}

// Sparse input (AtrousLevel::validIn/validOut, Dundr Sec. 5): about a quarter of the pixels
// valid, plus an 8x8 hole with no valid pixel that a step-1 3x3 level cannot fill. The GPU's
// first level reads validity as "> 0" from a history-length plane, later ones from 0/1 planes.
TEST(VulkanAtrous, MaskedLevelsMatchCpu) {
  RTD_REQUIRE_VULKAN();
  Fixture fx;
  Plane valid(kWidth, kHeight), length(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const bool hole = x >= 30 && x < 38 && y >= 20 && y < 28;
      const bool v = !hole && (x * 7 + y * 13) % 4 == 0;
      valid(x, y) = v ? 1.0f : 0.0f;
      length(x, y) = v ? float(1 + (x + y) % 5) : 0.0f;
    }
  PaddedPlane validIn, cpuValidOut;
  validIn.resize(kWidth, kHeight, 8);
  cpuValidOut.resize(kWidth, kHeight, 8);
  validIn.copyFrom(valid);
  vk::Planes gpuValidIn, gpuLength, gpuValidOut, out;
  fx.upload({valid}, gpuValidIn);
  fx.upload({Plane(kWidth, kHeight), length}, gpuLength);  // the length in plane 1
  gpuValidOut.allocate(fx.ctx, kWidth, kHeight, 1);
  out.allocate(fx.ctx, kWidth, kHeight, 5);
  const size_t n = size_t(kWidth) * kHeight;
  // Tolerances: where only a few taps are valid a pixel's value can rest on taps with small
  // weights (across the sphere's silhouette), whose relative error is that of the CPU's series
  // for w_n (normalExponent >= 16) rather than the 1e-5 of dense levels, where the centre's
  // weight 1 dominates: 1.7e-4 relative on a handful of pixels on lavapipe, the mean 7e-8.
  // With exponent 8 (exact powers on both sides) the dense tolerance holds.
  for (int exponent : {128, 8})
  for (AtrousKernel kernel : {AtrousKernel::B3Spline5x5, AtrousKernel::Binomial3x3})
    for (int step : {1, 4})
      for (bool fromLength : {false, true}) {
        AtrousLevel lv;
        lv.normalExponent = exponent;
        lv.kernel = kernel;
        lv.step = step;
        lv.propagateVariance = !fromLength;
        lv.validIn = &validIn;
        lv.validOut = &cpuValidOut;
        AtrousImage cpuOut;
        cpuOut.resize(kWidth, kHeight, 8);
        cpuOut.var = fx.in.var;
        atrousLevel(fx.guide, lv, fx.in, cpuOut);

        vk::GpuAtrousLevel g;
        g.radius = kernelRadius(kernel);
        g.step = step;
        g.normalExponent = exponent;
        g.propagateVariance = lv.propagateVariance;
        g.validIn = fromLength ? &gpuLength : &gpuValidIn;
        g.validInPlane = fromLength ? 1 : 0;
        g.validOut = &gpuValidOut;
        g.sharedTile = !fromLength;  // both the tiled shader and its untiled variant
        fx.run([&](vk::Recorder& rec) {
          vk::atrousGuide(rec, fx.gpu, 0.0f, fx.gradient);
          vk::atrousLevel(rec, fx.gpu, fx.gradient, g, fx.image, out);
        });
        const auto o = fx.download(out);
        const auto vo = fx.download(gpuValidOut);
        const std::string what = "kernel " + std::to_string(int(kernel)) + " step " + std::to_string(step) +
                                 (fromLength ? " from length" : "") + " exponent " + std::to_string(exponent);
        const PaddedPlane* want[5] = {&cpuOut.color[0], &cpuOut.color[1], &cpuOut.color[2], &cpuOut.lum, &cpuOut.var};
        for (int p = 0; p < 5; ++p) {
          EXPECT_LE(relError(o.data() + p * n, *want[p]), exponent < 16 ? 1e-5 : 5e-4) << what << " plane " << p;
          EXPECT_LE(meanRelError(o.data() + p * n, *want[p]), 1e-6) << what << " plane " << p;
        }
        int filled = 0, empty = 0;
        for (int y = 0; y < kHeight; ++y)
          for (int x = 0; x < kWidth; ++x) {
            const size_t i = size_t(y) * kWidth + x;
            ASSERT_EQ(vo[i], cpuValidOut.at(x, y)) << what << " at " << x << "," << y;
            // Independent of the CPU: an output is valid iff a tap of the kernel reaches a valid
            // input pixel (weights are positive there: same surface, similar luminance), and an
            // invalid output is exactly 0.
            bool reach = false;
            const int r = kernelRadius(kernel);
            for (int dy = -r; dy <= r; ++dy)
              for (int dx = -r; dx <= r; ++dx) {
                const int qx = x + dx * step, qy = y + dy * step;
                if (qx >= 0 && qy >= 0 && qx < kWidth && qy < kHeight && valid(qx, qy) > 0) reach = true;
              }
            if (vo[i] == 0.0f) {
              ++empty;
              EXPECT_FALSE(valid(x, y) > 0) << what << ": a valid pixel must stay valid";
              for (int p = 0; p < 3; ++p) ASSERT_EQ(o[p * n + i], 0.0f) << what;
            } else {
              ++filled;
              EXPECT_TRUE(reach) << what << ": valid without any valid tap at " << x << "," << y;
            }
          }
        if (kernel == AtrousKernel::Binomial3x3 && step == 1) { EXPECT_GT(empty, 0) << what << ": the hole stays"; }
        // Step 1 fills every gap of the pattern; with step 4 a pixel's taps share its position
        // in the pattern, so about the valid quarter stays valid.
        EXPECT_GT(filled, step == 1 ? int(n) * 3 / 4 : int(n) / 5) << what;
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
