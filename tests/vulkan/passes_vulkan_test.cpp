// The shared passes on Vulkan against their CPU versions (src/passes/), pass by pass, on the
// synthetic scene at 67x41: reprojection records, temporal accumulation, TAA.
#include <cstring>

#include "backend/vulkan/context.h"
#include "backend/vulkan/passes.h"
#include "core/frame_data.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "passes/taa_keys.h"
#include "passes/temporal_accumulation.h"
#include "download_planes.h"
#include "vulkan_test_util.h"

namespace rtd::test {
namespace {

vk::Context* context() {
  static std::unique_ptr<vk::Context> ctx = []() -> std::unique_ptr<vk::Context> {
    try {
      return std::make_unique<vk::Context>(DeviceDesc{.backend = Backend::Vulkan});
    } catch (const Error&) {
      return nullptr;
    }
  }();
  return ctx.get();
}

void uploadPlanes(vk::Context& ctx, const std::vector<Plane>& planes, vk::Planes& out) {
  const int w = planes[0].width, h = planes[0].height;
  out.allocate(ctx, w, h, int(planes.size()));
  std::vector<float> all;
  for (const auto& p : planes) all.insert(all.end(), p.data.begin(), p.data.end());
  ctx.upload(out.buffer, all.data(), all.size() * 4);
}

// The GPU twin of a CPU FrameData.
void toGpu(vk::Context& ctx, const FrameData& f, vk::GpuFrame& g) {
  g.width = f.width;
  g.height = f.height;
  for (int b = 0; b < kBufferCount; ++b) {
    g.present[b] = f.has(Buffer(b));
    if (g.present[b]) uploadPlanes(ctx, f.buffers[b], g.planes[b]);
  }
  g.cameraValue = f.camera;
  g.camera = vk::DeviceBuffer(ctx, 128, false);
  float m[32];
  std::memcpy(m, f.camera.worldToCamera.data(), 64);
  std::memcpy(m + 16, f.camera.projection.data(), 64);
  ctx.upload(g.camera, m, sizeof m);
}

FrameData toCpu(const Frame& frame, bool motion) {
  FrameInputs in = frame.inputs();
  if (!motion) in[Buffer::Motion] = {};
  FrameData d;
  importFrame(in, {Buffer::Color}, d);
  return d;
}

// Records `body` into a one-time command buffer and waits.
template <class F> void recordAndRun(vk::Context& ctx, F&& body) {
  vk::DescriptorCache cache(ctx);
  ctx.runOnce([&](VkCommandBuffer cmd) {
    vk::Recorder rec(ctx, cache, cmd, VK_NULL_HANDLE, 0);
    body(rec);
  });
}

#define REQUIRE_CONTEXT()  \
  RTD_REQUIRE_VULKAN();    \
  ASSERT_NE(context(), nullptr); \
  vk::Context& ctx = *context()

void checkReprojection(bool motion, const ReprojectionSettings& s) {
  vk::Context& ctx = *context();
  auto frames = syntheticFrames(3);
  FrameData f0 = toCpu(frames[0], motion), f1 = toCpu(frames[2], motion);  // two camera steps
  // Make all three kinds occur: a strip of flipped history normals two pixels wide rejects
  // both bilinear columns of the pixels over it (3x3 fallback), a block of new object ids
  // rejects every tap (none).
  for (int y = 0; y < kHeight; ++y)
    for (int c = 0; c < 3; ++c)
      for (int x = 20; x < 22; ++x) f0.plane(Buffer::Normal, c)(x, y) *= -1.0f;
  for (int y = 10; y < 15; ++y)
    for (int x = 40; x < 45; ++x) f1.plane(Buffer::ObjectId)(x, y) = 99.0f;
  Reprojection cpu;
  reproject(f1, &f0, s, cpu);

  vk::GpuFrame g0, g1;
  toGpu(ctx, f0, g0);
  toGpu(ctx, f1, g1);
  vk::Planes rp;
  rp.allocate(ctx, kWidth, kHeight, 8);
  recordAndRun(ctx, [&](vk::Recorder& rec) { vk::reproject(rec, g1, &g0, s, rp); });
  const std::vector<float> g = download(ctx, rp);
  const size_t n = size_t(kWidth) * kHeight;
  auto word = [&](int plane, size_t i) {
    uint32_t u;
    std::memcpy(&u, &g[plane * n + i], 4);
    return u;
  };
  const auto counts = cpu.counts();
  EXPECT_GT(counts[Reprojection::Bilinear], n / 2) << "the scene should reproject most pixels";
  EXPECT_GT(counts[Reprojection::None], 0u);
  if (s.positionTolerance == 0 && s.positionFootprints == 0) {  // else the 3x3 taps fail it too
    EXPECT_GT(counts[Reprojection::Fallback3x3], 0u);
  }
  for (size_t i = 0; i < n; ++i) {
    const uint32_t kind = word(0, i) & 3u;
    ASSERT_EQ(kind, cpu.kind[i]) << "pixel " << i % kWidth << "," << i / kWidth;
    EXPECT_NEAR(g[6 * n + i], cpu.prevX.data[i], 1e-4f);
    EXPECT_NEAR(g[7 * n + i], cpu.prevY.data[i], 1e-4f);
    if (kind == Reprojection::None) continue;
    EXPECT_EQ(int32_t(word(1, i)), cpu.base[i]);
    if (kind == Reprojection::Bilinear)
      for (int t = 0; t < 4; ++t) EXPECT_NEAR(g[(2 + t) * n + i], cpu.weights[i][t], 1e-5f);
    else
      EXPECT_EQ(word(0, i) >> 2, cpu.mask3x3[i]);
  }
}

TEST(VulkanPasses, ReprojectionMatchesCpuWithMotion) {
  RTD_REQUIRE_VULKAN();
  checkReprojection(true, {});
}

TEST(VulkanPasses, ReprojectionMatchesCpuFromCameraWithPositionTest) {
  RTD_REQUIRE_VULKAN();
  ReprojectionSettings s;
  s.positionTolerance = 0.05f;
  s.normalTolerance = 0.95f;
  checkReprojection(false, s);
}

// The scale-free position tolerance (BMFR's default: 4 pixel footprints), with motion vectors.
TEST(VulkanPasses, ReprojectionMatchesCpuWithFootprintPositionTest) {
  RTD_REQUIRE_VULKAN();
  ReprojectionSettings s;
  s.positionFootprints = 4.0f;
  checkReprojection(true, s);
}

// The GPU accumulator's planes (colour, both moments, history length; without moments colour
// and length) against the CPU's: within 1e-5 of the largest value, history lengths exactly.
void expectMatchesCpu(const std::vector<float>& out, const TemporalAccumulator& cpu, bool moments, int frame) {
  const size_t n = size_t(kWidth) * kHeight;
  std::vector<const Plane*> want = {&cpu.color()[0], &cpu.color()[1], &cpu.color()[2]};
  if (moments) want.insert(want.end(), {&cpu.moment1(), &cpu.moment2()});
  want.push_back(&cpu.historyLength());
  ASSERT_EQ(out.size(), want.size() * n);
  for (size_t p = 0; p < want.size(); ++p) {
    double maxErr = 0, maxRef = 0;
    for (size_t i = 0; i < n; ++i) {
      maxErr = std::max(maxErr, double(std::abs(out[p * n + i] - want[p]->data[i])));
      maxRef = std::max(maxRef, double(std::abs(want[p]->data[i])));
    }
    EXPECT_LE(maxErr, 1e-5 * maxRef) << "frame " << frame << " plane " << p;
    if (p + 1 == want.size()) { EXPECT_EQ(maxErr, 0.0) << "frame " << frame << ": history lengths are integers"; }
  }
}

// `count` frames of the synthetic scene through both accumulators, compared after each.
void accumulateOnBoth(vk::Context& ctx, bool moments, int count) {
  auto frames = syntheticFrames(count);
  TemporalAccumulator cpu;
  cpu.resize(kWidth, kHeight, moments);
  vk::GpuTemporalAccumulator gpu;
  gpu.resize(ctx, kWidth, kHeight, moments);
  EXPECT_EQ(gpu.bytes(), 2 * (moments ? 6 : 4) * 4 * size_t(kWidth) * kHeight);
  AccumulationOptions options;
  options.moments = moments;
  vk::Planes rp, color;
  rp.allocate(ctx, kWidth, kHeight, 8);
  vk::GpuFrame prevGpu;
  FrameData prevCpu;
  for (int k = 0; k < count; ++k) {
    FrameData f = toCpu(frames[size_t(k)], true);
    Reprojection r;
    reproject(f, k ? &prevCpu : nullptr, {}, r);
    Plane3 c{f.plane(Buffer::Color, 0), f.plane(Buffer::Color, 1), f.plane(Buffer::Color, 2)};
    cpu.run(r, c, 0.2f, 0.1f, 255, options);

    vk::GpuFrame g;
    toGpu(ctx, f, g);
    uploadPlanes(ctx, f.planes(Buffer::Color), color);
    recordAndRun(ctx, [&](vk::Recorder& rec) {
      vk::reproject(rec, g, k ? &prevGpu : nullptr, {}, rp);
      rec.barrier();
      gpu.run(rec, rp, color, 0.2f, 0.1f, 255);
    });
    expectMatchesCpu(download(ctx, gpu.current()), cpu, moments, k);
    prevCpu = std::move(f);
    prevGpu = std::move(g);
  }
  EXPECT_EQ(cpu.historyLength().data[size_t(kHeight / 2) * kWidth + kWidth / 2], float(count));
}

TEST(VulkanPasses, TemporalAccumulationMatchesCpu) {
  REQUIRE_CONTEXT();
  accumulateOnBoth(ctx, true, 4);
}

// Without moments (BMFR's phase I, TemporalAccumulator::resize(w, h, false)): four planes per
// history (colour, length), the length in plane 3 (GpuTemporalAccumulator::lengthPlane).
TEST(VulkanPasses, TemporalAccumulationWithoutMomentsMatchesCpu) {
  REQUIRE_CONTEXT();
  accumulateOnBoth(ctx, false, 3);
  vk::GpuTemporalAccumulator gpu;
  gpu.resize(ctx, kWidth, kHeight, false);
  EXPECT_EQ(gpu.lengthPlane(), 3);
}

// Progressive mode (AccumulationOptions::sampleMask, Dundr Sec. 5): unsampled pixels carry
// their history over unchanged, or stay missing (length 0) without one; lengths exact.
TEST(VulkanPasses, TemporalAccumulationWithSampleMaskMatchesCpu) {
  REQUIRE_CONTEXT();
  auto frames = syntheticFrames(5);
  TemporalAccumulator cpu;
  cpu.resize(kWidth, kHeight);
  vk::GpuTemporalAccumulator gpu;
  gpu.resize(ctx, kWidth, kHeight);
  vk::Planes rp, color, mask;
  rp.allocate(ctx, kWidth, kHeight, 8);
  vk::GpuFrame prevGpu;
  FrameData prevCpu;
  const size_t n = size_t(kWidth) * kHeight;
  size_t carried = 0, missing = 0;
  for (int k = 0; k < 5; ++k) {
    FrameData f = toCpu(frames[size_t(k)], true);
    Plane m(kWidth, kHeight);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) m(x, y) = ((x & 1) + 2 * (y & 1)) == k % 4 ? 1.0f : 0.0f;
    Reprojection r;
    reproject(f, k ? &prevCpu : nullptr, {}, r);
    Plane3 c{f.plane(Buffer::Color, 0), f.plane(Buffer::Color, 1), f.plane(Buffer::Color, 2)};
    const std::vector<float> before = k ? download(ctx, gpu.current()) : std::vector<float>();
    AccumulationOptions opt;
    opt.sampleMask = &m;
    cpu.run(r, c, 0.2f, 0.1f, 255, opt);

    vk::GpuFrame g;
    toGpu(ctx, f, g);
    uploadPlanes(ctx, f.planes(Buffer::Color), color);
    uploadPlanes(ctx, {m}, mask);
    recordAndRun(ctx, [&](vk::Recorder& rec) {
      vk::reproject(rec, g, k ? &prevGpu : nullptr, {}, rp);
      rec.barrier();
      gpu.run(rec, rp, color, 0.2f, 0.1f, 255, 0, true, &mask);
    });
    const std::vector<float> out = download(ctx, gpu.current());
    expectMatchesCpu(out, cpu, true, k);
    // Independent of the CPU: an unsampled pixel with an exact (integer) reprojection keeps the
    // value of the pixel it came from; one without history stays at length 0.
    for (size_t i = 0; i < n; ++i) {
      if (m.data[i] != 0.0f) continue;
      if (r.kind[i] == Reprojection::None) {
        EXPECT_EQ(out[5 * n + i], 0.0f);
        ++missing;
      } else if (r.kind[i] == Reprojection::Bilinear && r.weights[i][0] == 1.0f) {
        for (int p = 0; p < 6; ++p) EXPECT_EQ(out[p * n + i], before[p * n + size_t(r.base[i])]) << "plane " << p;
        ++carried;
      }
    }
    prevCpu = std::move(f);
    prevGpu = std::move(g);
  }
  EXPECT_GT(missing, n / 2) << "frame 0: three quarters of the pixels have neither sample nor history";
  EXPECT_GT(carried, 0u) << "some unsampled pixels should reproject exactly onto one pixel";
}

// In both domains, with both neighbourhoods and both history filters.
TEST(VulkanPasses, TaaMatchesCpu) {
  REQUIRE_CONTEXT();
  auto frames = syntheticFrames(3);
  struct Config {
    TaaDomain domain;
    TaaNeighbourhood shape;
    TaaHistoryFilter filter;
    bool rejection = false;
    float subpixelAlpha = 0.0f;
  };
  for (const Config& config : {Config{TaaDomain::linear, TaaNeighbourhood::box3x3, TaaHistoryFilter::bilinear},
                               Config{TaaDomain::display, TaaNeighbourhood::box3x3, TaaHistoryFilter::bilinear},
                               Config{TaaDomain::display, TaaNeighbourhood::boxCross, TaaHistoryFilter::bilinear},
                               Config{TaaDomain::linear, TaaNeighbourhood::box3x3, TaaHistoryFilter::catmullRom},
                               Config{TaaDomain::display, TaaNeighbourhood::box3x3, TaaHistoryFilter::catmullRom},
                               Config{TaaDomain::display, TaaNeighbourhood::boxCross, TaaHistoryFilter::catmullRom},
                               Config{TaaDomain::display, TaaNeighbourhood::box3x3, TaaHistoryFilter::bilinear, true},
                               Config{TaaDomain::linear, TaaNeighbourhood::boxCross, TaaHistoryFilter::catmullRom, true},
                               Config{TaaDomain::display, TaaNeighbourhood::box3x3, TaaHistoryFilter::catmullRom, false, 2.0f}}) {
    TaaSettings s;
    s.taaDomain = config.domain;
    s.taaNeighbourhood = config.shape;
    s.taaHistoryFilter = config.filter;
    s.taaHistoryRejection = config.rejection;
    s.taaSubpixelAlpha = config.subpixelAlpha;
    // With rejection, a depth test tight enough that the synthetic scene's motion fails it at
    // some pixels (it has no disocclusion of its own), without the 3x3 fallback.
    ReprojectionSettings rs;
    if (config.rejection) {
      rs.depthTolerance = 1e-4f;
      rs.depthGradientScale = 0.0f;
      rs.fallback3x3 = false;
    }
    const std::string name = std::string(config.domain == TaaDomain::linear ? "linear" : "display") +
                             (config.shape == TaaNeighbourhood::box3x3 ? " box3x3" : " boxCross") +
                             (config.filter == TaaHistoryFilter::bilinear ? " bilinear" : " catmullRom") +
                             (config.rejection ? " rejection" : "") +
                             (config.subpixelAlpha > 0 ? " subpixelAlpha " + std::to_string(config.subpixelAlpha) : "");
    Taa cpu, constantAlpha;  // constantAlpha: the config with taaSubpixelAlpha 0, to show the option acts
    cpu.resize(kWidth, kHeight);
    TaaSettings constantS = s;
    constantS.taaSubpixelAlpha = 0.0f;
    vk::GpuTaa gpu;
    gpu.resize(kWidth, kHeight);
    vk::Planes rp, color;
    rp.allocate(ctx, kWidth, kHeight, 8);
    FrameData prevCpu;
    vk::GpuFrame prevGpu;
    for (int k = 0; k < 3; ++k) {
      FrameData f = toCpu(frames[size_t(k)], true);
      Reprojection r;
      reproject(f, k ? &prevCpu : nullptr, rs, r);
      Plane3 c{f.plane(Buffer::Color, 0), f.plane(Buffer::Color, 1), f.plane(Buffer::Color, 2)};
      const Plane3& cpuOut = cpu.run(r, c, s);
      if (config.subpixelAlpha > 0) {
        const Plane3& plain = constantAlpha.run(r, c, constantS);
        double moved = 0;
        for (int p = 0; p < 3; ++p)
          for (size_t i = 0; i < plain[p].data.size(); ++i)
            moved = std::max(moved, double(std::abs(plain[p].data[i] - cpuOut[p].data[i])));
        if (k > 0) { EXPECT_GT(moved, 1e-3) << "taaSubpixelAlpha changed nothing on frame " << k << " (" << name << ")"; }
      }

      vk::GpuFrame g;
      toGpu(ctx, f, g);
      uploadPlanes(ctx, f.planes(Buffer::Color), color);
      const vk::Planes* result = nullptr;
      recordAndRun(ctx, [&](vk::Recorder& rec) {
        vk::reproject(rec, g, k ? &prevGpu : nullptr, rs, rp);
        result = &gpu.run(rec, rp, color, s);
      });
      const std::vector<float> out = download(ctx, *result);
      const size_t n = size_t(kWidth) * kHeight;
      double maxErr = 0, maxRef = 0, changed = 0;
      for (int p = 0; p < 3; ++p)
        for (size_t i = 0; i < n; ++i) {
          maxErr = std::max(maxErr, double(std::abs(out[p * n + i] - cpuOut[p].data[i])));
          maxRef = std::max(maxRef, double(std::abs(cpuOut[p].data[i])));
          changed = std::max(changed, double(std::abs(cpuOut[p].data[i] - c[p].data[i])));
        }
      EXPECT_LE(maxErr, 1e-5 * maxRef) << name << ", frame " << k;
      if (k > 0) { EXPECT_GT(changed, 0.1) << "TAA should blend history on frame " << k << " (" << name << ")"; }
      if (k > 0 && config.rejection) { EXPECT_GT(r.counts()[Reprojection::None], 0u) << "no disocclusion to reject"; }
      prevCpu = std::move(f);
      prevGpu = std::move(g);
    }
  }
}

// The own-surface box (TaaSettings::taaOwnSurface): the keys of taa_keys.comp equal the CPU's
// (object ids of the synthetic scene, emitters added here), and the keyed TAA matches the CPU
// within TaaMatchesCpu's tolerance, in both domains and both neighbourhoods; the keys change
// the result (the keyed CPU output differs from the plain one).
TEST(VulkanPasses, TaaOwnSurfaceMatchesCpu) {
  REQUIRE_CONTEXT();
  auto frames = syntheticFrames(3);
  EmitterSettings e;
  e.excludeEmitters = true;
  for (TaaDomain domain : {TaaDomain::linear, TaaDomain::display})
    for (TaaNeighbourhood shape : {TaaNeighbourhood::box3x3, TaaNeighbourhood::boxCross}) {
      TaaSettings s;
      s.taaDomain = domain;
      s.taaNeighbourhood = shape;
      s.taaOwnSurface = true;
      const std::string name = std::string(domain == TaaDomain::linear ? "linear" : "display") +
                               (shape == TaaNeighbourhood::box3x3 ? " box3x3" : " boxCross");
      Taa cpu, plain;
      vk::GpuTaa gpu;
      gpu.resize(kWidth, kHeight);
      vk::Planes rp, color, keysGpu;
      rp.allocate(ctx, kWidth, kHeight, 8);
      FrameData prevCpu;
      vk::GpuFrame prevGpu;
      double keyedChange = 0;
      for (int k = 0; k < 3; ++k) {
        FrameData f = toCpu(frames[size_t(k)], true);
        std::vector<Plane>& em = f.buffers[int(Buffer::Emission)];
        em.assign(3, Plane{});
        for (Plane& p : em) p.resize(kWidth, kHeight, 0.0f);
        for (int y = 0; y < kHeight; ++y)
          for (int x = 0; x < kWidth; ++x)
            if ((x * 7 + y * 3 + k) % 11 == 0) em[1](x, y) = 5.0f;
        PixelVector<uint32_t> keys;
        ASSERT_TRUE(taaSurfaceKeys(f, &e, nullptr, keys));
        Reprojection r;
        reproject(f, k ? &prevCpu : nullptr, {}, r);
        Plane3 c{f.plane(Buffer::Color, 0), f.plane(Buffer::Color, 1), f.plane(Buffer::Color, 2)};
        const Plane3& cpuOut = cpu.run(r, c, s, &keys);
        TaaSettings off = s;
        off.taaOwnSurface = false;
        const Plane3& plainOut = plain.run(r, c, off);

        vk::GpuFrame g;
        toGpu(ctx, f, g);
        uploadPlanes(ctx, f.planes(Buffer::Color), color);
        const vk::Planes* result = nullptr;
        bool keyed = false;
        recordAndRun(ctx, [&](vk::Recorder& rec) {
          vk::reproject(rec, g, k ? &prevGpu : nullptr, {}, rp);
          keyed = vk::taaSurfaceKeys(rec, g, &e, nullptr, keysGpu);
          rec.barrier();
          result = &gpu.run(rec, rp, color, s, &keysGpu);
        });
        ASSERT_TRUE(keyed);
        const std::vector<float> keyBits = download(ctx, keysGpu);
        const size_t n = size_t(kWidth) * kHeight;
        size_t keyMismatch = 0;
        for (size_t i = 0; i < n; ++i) {
          uint32_t v;
          std::memcpy(&v, &keyBits[i], 4);
          keyMismatch += v != keys[i];
        }
        EXPECT_EQ(keyMismatch, 0u) << name << ", frame " << k;
        const std::vector<float> out = download(ctx, *result);
        double maxErr = 0, maxRef = 0;
        for (int p = 0; p < 3; ++p)
          for (size_t i = 0; i < n; ++i) {
            maxErr = std::max(maxErr, double(std::abs(out[p * n + i] - cpuOut[p].data[i])));
            maxRef = std::max(maxRef, double(std::abs(cpuOut[p].data[i])));
            keyedChange = std::max(keyedChange, double(std::abs(cpuOut[p].data[i] - plainOut[p].data[i])));
          }
        EXPECT_LE(maxErr, 1e-5 * maxRef) << name << ", frame " << k;
        prevCpu = std::move(f);
        prevGpu = std::move(g);
      }
      EXPECT_GT(keyedChange, 1e-3) << name << ": the keys should change some pixel's box";
    }
}

}  // namespace
}  // namespace rtd::test
