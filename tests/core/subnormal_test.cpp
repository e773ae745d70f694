// No subnormal floats in the CPU hot loops (src/core/flush.h, issue 20), whatever the input:
// every weight function, every pass and every plane of whole SVGF, BMFR and accumulate frames
// on extreme inputs (huge luminance differences, normals at right angles, depth jumps of 1e6,
// variances of 0 and 1e30, radiance that decays through the subnormal range). Two checks:
// std::fpclassify on every stored value, and the MXCSR exception flags, which record any
// subnormal operand (DE) or underflowing result (UE) of any SSE/AVX instruction the thread ran
// (the passes run on a one-thread arena, i.e. on the test's thread). The suite itself runs
// with flush-to-zero and denormals-are-zero off, the default, which the first test asserts.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <mutex>
#include <random>
#include <set>
#include <string>

#include "backend/cpu/cpu_denoiser.h"
#include "core/flush.h"
#include "passes/atrous.h"
#include "passes/temporal_accumulation.h"
#include "rtd/rtd.h"
#include "support/cpu_paths.h"

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#define RTD_TEST_MXCSR 1
#endif

namespace rtd {
namespace {

#ifdef RTD_TEST_MXCSR
constexpr unsigned kDenormalFlag = 0x0002, kUnderflowFlag = 0x0010, kFlushToZero = 0x8000, kDenormalsAreZero = 0x0040;
#endif

/// Clears this thread's floating-point exception flags; raised() tells whether any
/// instruction since then had a subnormal operand or an underflowing result.
struct SubnormalProbe {
  SubnormalProbe() { clear(); }
  void clear() {
#ifdef RTD_TEST_MXCSR
    _mm_setcsr(_mm_getcsr() & ~0x3fu);
#endif
  }
  bool raised() const {
#ifdef RTD_TEST_MXCSR
    return (_mm_getcsr() & (kDenormalFlag | kUnderflowFlag)) != 0;
#else
    return false;
#endif
  }
};

bool subnormal(float v) { return std::fpclassify(v) == FP_SUBNORMAL; }

size_t countSubnormals(const float* p, size_t n) {
  size_t c = 0;
  for (size_t i = 0; i < n; ++i) c += subnormal(p[i]);
  return c;
}

TEST(Subnormal, TestProcessRunsWithFlushToZeroOff) {
#ifdef RTD_TEST_MXCSR
  auto modeBits = [] { return _mm_getcsr() & (kFlushToZero | kDenormalsAreZero); };
  EXPECT_EQ(modeBits(), 0u) << "the suite must run in the default floating-point mode";
  // Run a denoiser: the library must leave the caller's mode alone, on this thread and on the
  // worker threads.
  auto denoiser = Device::create()->createDenoiser("svgf");
  Frame f;
  const int w = 32, h = 16;
  f.width = w;
  f.height = h;
  f[Buffer::Color] = Image(w, h, 3, 0.5f);
  f[Buffer::Depth] = Image(w, h, 1, 1.0f);
  f[Buffer::Normal] = Image(w, h, 3, 0.0f);
  for (int i = 0; i < w * h; ++i) f[Buffer::Normal].pixels[size_t(i) * 3 + 2] = 1.0f;
  Image out(w, h, 3);
  for (int i = 0; i < 3; ++i) denoiser->denoise(f.inputs(), out.view());
  EXPECT_EQ(modeBits(), 0u);
  std::mutex m;
  std::set<unsigned> seen;
  tbb::parallel_for(0, 64, [&](int) {
    std::lock_guard lock(m);
    seen.insert(modeBits());
  });
  EXPECT_EQ(seen, std::set<unsigned>{0u});
#else
  GTEST_SKIP() << "MXCSR is x86 only";
#endif
}

// ---------------------------------------------------------------- weight functions

TEST(Subnormal, WeightFunctionsAreZeroOrNormal) {
  const float depths[] = {0.0f, 1e-20f, 0.5f, 1.0f, 1e6f, 3e38f};
  const float gradients[] = {0.0f, 1e-30f, 1e-3f, 1.0f, 1e6f, 1e30f};
  const float cosines[] = {-1.0f, 0.0f, 1e-30f, 1e-10f, 0.1f, 0.5f, 0.9f, 0.99f, 0.9999f, 1.0f};
  const int exponents[] = {1, 2, 3, 8, 64, 128, 1000};
  const float lums[] = {0.0f, 1e-15f, 1e-6f, 1.0f, 1e6f, 1e18f};
  const float scales[] = {0.0f, 1e-15f, 1.0f, 1e15f};  // sqrt of variances 0 .. 1e30
  SubnormalProbe probe;
  size_t count = 0, zeros = 0;
  auto check = [&](float v) {
    EXPECT_FALSE(subnormal(v)) << v;
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
    zeros += v == 0.0f;
    ++count;
  };
  for (float zp : depths)
    for (float zq : depths)
      for (float g : gradients)
        for (float eps : {1e-2f, 1e-6f}) check(depthWeight(zp, zq, g, 1.0f, eps));
  for (float c : cosines)
    for (int e : exponents) check(normalWeight(c, e));
  for (float lp : lums)
    for (float lq : lums)
      for (float s : scales)
        for (float eps : {1e-10f, 0.05f}) check(luminanceWeight(lp, lq, 4.0f, s, eps));
  EXPECT_FALSE(probe.raised()) << "a weight function computed with a subnormal";
  // The extremes do reach the cut-off, where the weights are exactly 0.
  EXPECT_GT(zeros, count / 4);
  EXPECT_EQ(depthWeight(1.0f, 1e6f, 1.0f, 1.0f, 1e-2f), 0.0f);
  EXPECT_EQ(normalWeight(0.5f, 128), 0.0f);  // 2^-128 would be subnormal
  EXPECT_EQ(luminanceWeight(0.0f, 1e6f, 4.0f, 1.0f, 1e-10f), 0.0f);
  // Just inside the cut-off they are not.
  EXPECT_GT(normalWeight(std::exp2(-23.0f / 128.0f), 128), 0.0f);
  EXPECT_GT(depthWeight(0.0f, 16.0f, 0.0f, 1.0f, 1.0f), 0.0f);  // e^-16 > 2^-24
  EXPECT_EQ(depthWeight(0.0f, 17.0f, 0.0f, 1.0f, 1.0f), 0.0f);  // e^-17 < 2^-24
}

// ---------------------------------------------------------------- the a-trous pass

// Extreme guide features and signals on a w x h image: depths 1 or 1e6, normals along random
// axes (neighbours at right angles or opposite), gradients 0 to 1e6, colours from 0 to 1e18,
// variances 0, 1e-18, 1 or 1e30.
struct ExtremeImage {
  int w = 37, h = 23;
  AtrousGuide guide;
  AtrousImage in, out;
  PaddedPlane scale, validIn, validOut;
  explicit ExtremeImage(int pad) {
    guide.resize(w, h, pad);
    in.resize(w, h, pad);
    out.resize(w, h, pad);
    scale.resize(w, h, pad);
    validIn.resize(w, h, pad);
    validOut.resize(w, h, pad);
    std::mt19937 rng(7);
    auto pick = [&](std::initializer_list<float> v) { return *(v.begin() + rng() % v.size()); };
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        guide.depth.at(x, y) = pick({1.0f, 1.0f, 1e6f});
        const int axis = int(rng() % 3);
        guide.normal[axis].at(x, y) = pick({1.0f, -1.0f, 1.0f});
        guide.gradX.at(x, y) = pick({0.0f, 1e-3f, 1.0f, 1e6f});
        guide.gradY.at(x, y) = pick({0.0f, 1e-3f, 1.0f, 1e6f});
        for (int c = 0; c < 3; ++c) in.color[c].at(x, y) = pick({0.0f, 1e-15f, 1.0f, 1e6f, 1e18f});
        // (Values below kTiny never reach the pass: import flushes them, passes flush what
        // they store; the whole-frame tests below cover that.)
        in.lum.at(x, y) = luminance(in.color[0].at(x, y), in.color[1].at(x, y), in.color[2].at(x, y));
        in.var.at(x, y) = pick({0.0f, 1e-18f, 1.0f, 1e30f});
        scale.at(x, y) = pick({1.0f, 1.0f, 0.0f, 8.0f});
        validIn.at(x, y) = pick({1.0f, 0.0f});
      }
  }
  size_t outputSubnormals() const {
    size_t n = 0;
    for (const PaddedPlane* p : {&out.color[0], &out.color[1], &out.color[2], &out.lum, &out.var, &validOut})
      n += countSubnormals(p->data.data(), p->data.size());
    return n;
  }
};

// Without FMA (the sse2 path) a tiny product of a weight's exponent is rounded on its own: the
// stored values are checked there, the instruction flags only on the paths with FMA.
bool probeApplies(CpuPath p) { return p != CpuPath::Sse2; }

TEST(Subnormal, AtrousLevelsOnExtremeInputs) {
  for (CpuPath path : test::supportedCpuPaths()) {
  test::ScopedCpuPath force(path);
  tbb::task_arena one(1);  // the passes run on this thread, so the probe sees everything
  one.execute([path] {
    ExtremeImage im(32);
    for (AtrousKernel kernel : {AtrousKernel::B3Spline5x5, AtrousKernel::Binomial3x3})
      for (int step : {1, 2, 16})
        for (int exponent : {128, 64, 8, 3})
          for (bool masked : {false, true})
            for (bool varianceScale : {false, true}) {
              AtrousLevel lv;
              lv.kernel = kernel;
              lv.step = step;
              lv.normalExponent = exponent;
              lv.varianceScale = varianceScale;
              lv.sigmaScale = &im.scale;
              lv.validIn = masked ? &im.validIn : nullptr;
              lv.validOut = masked ? &im.validOut : nullptr;
              const std::string what = std::string(cpuPathName(path)) + " kernel " + std::to_string(int(kernel)) + " step " + std::to_string(step) +
                                       " exponent " + std::to_string(exponent) + (masked ? " masked" : "") +
                                       (varianceScale ? " variance scale" : "");
              SubnormalProbe probe;
              atrousLevel(im.guide, lv, im.in, im.out);
              if (probeApplies(path)) {
                EXPECT_FALSE(probe.raised()) << what;
              }
              EXPECT_EQ(im.outputSubnormals(), 0u) << what;
            }
    // The spatial variance estimate (every pixel short-history) and the once-only g3x3.
    Plane len(im.w, im.h, 1.0f);
    for (int exponent : {128, 8}) {
      SubnormalProbe probe;
      spatialVariance(im.guide, im.in.lum, im.in.color[0], len, 4.0f, 3, 1.0f, 1e-2f, 0.0f, exponent, im.out.var);
      gaussian3x3(im.out.var, im.out.lum);
      if (probeApplies(path)) {
        EXPECT_FALSE(probe.raised()) << cpuPathName(path) << " " << exponent;
      }
      EXPECT_EQ(im.outputSubnormals(), 0u) << cpuPathName(path) << " " << exponent;
    }
  });
  }
}

// ---------------------------------------------------------------- whole frames

// Frame `t` of an extreme sequence: random per-pixel extremes that stay fixed over time
// (seeded per pixel), a block of pixels whose radiance alternates between 0 and 1e15 (a
// luminance variance of ~1e30), one whose radiance is 1e-17 or 1e-36 on frame 0 and 0 afterwards
// (the history decays into the subnormal range unless flushed), a constant block (variance 0),
// and a motion that moves part of the image by a fraction of a pixel and part out of it.
Frame extremeFrame(int t, int w, int h) {
  Frame f;
  f.width = w;
  f.height = h;
  f[Buffer::Color] = Image(w, h, 3);
  f[Buffer::Albedo] = Image(w, h, 3);
  f[Buffer::Normal] = Image(w, h, 3);
  f[Buffer::Depth] = Image(w, h, 1);
  f[Buffer::Position] = Image(w, h, 3);
  f[Buffer::Motion] = Image(w, h, 2);
  f[Buffer::ObjectId] = Image(w, h, 1);
  f[Buffer::Roughness] = Image(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::mt19937 rng(uint32_t(y * w + x) * 2654435761u);
      auto pick = [&](std::initializer_list<float> v) { return *(v.begin() + rng() % v.size()); };
      const size_t i = size_t(y) * w + x;
      float* c = &f[Buffer::Color].pixels[3 * i];
      const float noise = std::uniform_real_distribution<float>(0.5f, 1.5f)(rng);
      // Subnormal (1e-40) and tiny radiance too: import flushes them.
      const float base = pick({0.0f, 1e-40f, 1e-36f, 1e-30f, 1e-15f, 1e-6f, 1.0f, 1e6f, 1e18f});
      for (int k = 0; k < 3; ++k) c[k] = base * (t % 2 ? noise : 1.0f / noise);
      if (x < 8 && y < 8) c[0] = c[1] = c[2] = t % 2 ? 1e15f : 0.0f;    // variance ~1e30
      if (x >= 8 && x < 16 && y < 8) c[0] = c[1] = c[2] = t == 0 ? (y < 4 ? 1e-17f : 1e-36f) : 0.0f;  // decays
      if (x >= 16 && x < 24 && y < 8) c[0] = c[1] = c[2] = 0.25f;      // variance 0
      float* a = &f[Buffer::Albedo].pixels[3 * i];
      for (int k = 0; k < 3; ++k) a[k] = pick({0.0f, 1e-30f, 0.5f, 1.0f});
      float* n = &f[Buffer::Normal].pixels[3 * i];
      n[rng() % 3] = pick({1.0f, -1.0f, 1.0f, 0.0f});  // at right angles, opposite, or background
      n[rng() % 3] += pick({0.0f, 0.0f, 1e-30f, -1e-39f});  // tiny components
      const float z = pick({1.0f, 1.0f, 1e6f, 1e-30f});
      f[Buffer::Depth].pixels[i] = z;
      float* p = &f[Buffer::Position].pixels[3 * i];
      p[0] = float(x) * 1e-3f * z;
      p[1] = float(y) * 1e-3f * z;
      p[2] = z;
      float* m = &f[Buffer::Motion].pixels[2 * i];
      m[0] = x < w / 2 ? 0.25f : pick({0.0f, -1.0f, 3.5f, 1e6f});
      m[1] = y < h / 2 ? 0.0f : pick({0.0f, 0.5f, -1e6f});
      f[Buffer::ObjectId].pixels[i] = float(rng() % 3);
      f[Buffer::Roughness].pixels[i] = pick({0.0f, 0.5f, 1.0f});
    }
  return f;
}

void checkWholeFrames(const std::string& method, const std::vector<std::string>& settings, CpuPath path);

// On every CPU path this machine runs.
void checkWholeFrames(const std::string& method, const std::vector<std::string>& settings) {
  for (CpuPath path : test::supportedCpuPaths()) checkWholeFrames(method, settings, path);
}

void checkWholeFrames(const std::string& method, const std::vector<std::string>& settings, CpuPath path) {
  test::ScopedCpuPath force(path);
  const int w = 56, h = 40;
  std::vector<Frame> frames;
  for (int t = 0; t < 12; ++t) frames.push_back(extremeFrame(t, w, h));
  auto denoiser = Device::create({.backend = Backend::Cpu, .threads = 1})->createDenoiser(method);
  for (const std::string& kv : settings) {
    const size_t eq = kv.find('=');
    denoiser->set(kv.substr(0, eq), kv.substr(eq + 1));
  }
  const auto* inspect = dynamic_cast<const PlaneInspection*>(denoiser.get());
  ASSERT_NE(inspect, nullptr);
  Image out(w, h, 3);
  for (int t = 0; t < 12; ++t) {
    const std::string what = method + " on " + cpuPathName(path) + ", frame " + std::to_string(t);
    SubnormalProbe probe;
    denoiser->denoise(frames[size_t(t)].inputs(), out.view());
    if (probeApplies(path)) {
      EXPECT_FALSE(probe.raised()) << what << ": an instruction had a subnormal operand or result";
    }
    size_t planes = 0;
    inspect->forEachPlane([&](std::string_view name, const float* p, size_t n) {
      ++planes;
      EXPECT_EQ(countSubnormals(p, n), 0u) << what << ", plane " << name;
    });
    EXPECT_GT(planes, 10u);
    EXPECT_EQ(countSubnormals(out.pixels.data(), out.pixels.size()), 0u) << what;
  }
}

TEST(Subnormal, SvgfFramesOnExtremeInputs) { checkWholeFrames("svgf", {}); }
TEST(Subnormal, SvgfVariantFramesOnExtremeInputs) {
  checkWholeFrames("svgf", {"variant=dundr"});
  checkWholeFrames("svgf", {"variant=voorhuis"});
  checkWholeFrames("svgf", {"variant=gersthofer", "sigmaNormal=8"});
}
TEST(Subnormal, BmfrFramesOnExtremeInputs) {
  checkWholeFrames("bmfr", {});
  checkWholeFrames("bmfr", {"featureRoughness=true", "samplesPerBlock=36", "noiseAmount=0"});
}
TEST(Subnormal, AccumulateFramesOnExtremeInputs) { checkWholeFrames("accumulate", {}); }

}  // namespace
}  // namespace rtd
