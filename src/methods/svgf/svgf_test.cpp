// Tests of the shared a-trous pass and of the SVGF method (Schied et al. 2017 and variants).
#include <gtest/gtest.h>

#include <atomic>
#include <map>
#include <cmath>
#include <random>

#include "methods/svgf/svgf_filter.h"
#include "methods/svgf/svgf_passes.h"
#include "passes/atrous.h"
#include "rtd/rtd.h"
#include "support/cpu_paths.h"
#include "support/planes_kept.h"
#include "support/runs_as_fresh.h"
#include "synthetic/synthetic.h"

namespace rtd {
namespace {

// ---------------------------------------------------------------- edge-stopping weights

TEST(AtrousWeights, DepthWeightMatchesHandValues) {
  // |1.0 - 1.2| / (1 * |0.1| + 0) = 2 -> e^-2
  EXPECT_NEAR(depthWeight(1.0f, 1.2f, 0.1f, 1.0f, 0.0f), 0.1353352832f, 1e-6);
  // sigma_z = 2 and a negative gradient.offset: 0.2 / (2 * 0.1 + 0.05) = 0.8 -> e^-0.8
  EXPECT_NEAR(depthWeight(1.0f, 1.2f, -0.1f, 2.0f, 0.05f), 0.4493289641f, 1e-6);
  // Equal depths: weight 1 whatever the gradient.
  EXPECT_FLOAT_EQ(depthWeight(3.0f, 3.0f, 0.0f, 1.0f, 1e-2f), 1.0f);
}

TEST(AtrousWeights, NormalWeightMatchesHandValues) {
  EXPECT_FLOAT_EQ(normalWeight(1.0f, 128), 1.0f);
  EXPECT_FLOAT_EQ(normalWeight(0.0f, 64), 0.0f);
  EXPECT_FLOAT_EQ(normalWeight(-0.5f, 64), 0.0f);  // back-facing: clamped to 0
  // cos(10 deg)^64 = exp(64 ln 0.984807753) = exp(-0.979659) = 0.375399
  EXPECT_NEAR(normalWeight(std::cos(10.0f * 3.14159265f / 180.0f), 64), 0.375399, 2e-5);
  EXPECT_NEAR(normalWeight(0.5f, 2), 0.25, 1e-7);
}

TEST(AtrousWeights, LuminanceWeightMatchesHandValues) {
  // |0.5 - 0.3| / (4 * sqrt(0.01)) = 0.5 -> e^-0.5
  EXPECT_NEAR(luminanceWeight(0.5f, 0.3f, 4.0f, std::sqrt(0.01f), 0.0f), 0.6065306597f, 1e-6);
  // Dundr's variance scale: 0.2 / (4 * 0.01 + 0.01) = 4 -> e^-4
  EXPECT_NEAR(luminanceWeight(0.5f, 0.3f, 4.0f, 0.01f, 0.01f), 0.0183156389f, 1e-7);
}

TEST(AtrousWeights, VoorhuisBandwidthScale) {
  // Eq. 8: h = 0..10 -> 8, 7, 6, 5, 4, 3, 2, 1, 1, 1, 1
  const float expected[11] = {8, 7, 6, 5, 4, 3, 2, 1, 1, 1, 1};
  for (int h = 0; h <= 10; ++h) EXPECT_EQ(shortHistoryBandwidthScale(h), expected[h]) << h;
}

// ---------------------------------------------------------------- a-trous pass

struct Scene {
  int w, h;
  AtrousGuide guide;
  AtrousImage a, b;
  PaddedPlane inv;
  Scene(int width, int height, int pad) : w(width), h(height) {
    guide.resize(w, h, pad);
    a.resize(w, h, pad);
    b.resize(w, h, pad);
    inv.resize(w, h, pad);
  }
  // Flat plane facing the camera at depth z (gradient 0), normal +z.
  void flat(float z = 5.0f) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        guide.depth.at(x, y) = z;
        guide.normal[2].at(x, y) = 1.0f;
      }
  }
};

// `scale`: per-pixel multiplier of sigma_l (0 = luminance weight off).
AtrousLevel level(AtrousKernel k, int step, const PaddedPlane* scale) {
  AtrousLevel lv;
  lv.kernel = k;
  lv.step = step;
  lv.sigmaScale = scale;
  lv.sigmaLuminance = 4.0f;
  lv.luminanceEpsilon = 1e-4f;
  return lv;
}

// 1 / (sigma_l k sqrt(g3x3(Var)) + eps) at p, the zero border counted as variance 0.
double referenceInvBandwidth(const Scene& s, const AtrousLevel& lv, int x, int y) {
  const double k = lv.sigmaScale ? lv.sigmaScale->at(x, y) : 1.0;
  if (k == 0.0) return 0.0;
  double v = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = x + dx, qy = y + dy;
      if (qx < 0 || qy < 0 || qx >= s.w || qy >= s.h) continue;
      v += (dx ? 0.5 : 1.0) * (dy ? 0.5 : 1.0) * 0.25 * s.a.var.at(qx, qy);
    }
  const double sd = lv.varianceScale ? v : std::sqrt(v);
  return 1.0 / (lv.sigmaLuminance * k * sd + lv.luminanceEpsilon);
}

// Double-precision evaluation of Schied et al. Eq. 3-5 at one pixel, written from the paper.
void referencePixel(const Scene& s, const AtrousLevel& lv, int x, int y, double out[3], double& var) {
  const int r = lv.kernel == AtrousKernel::B3Spline5x5 ? 2 : 1;
  const double b3[5] = {1 / 16.0, 1 / 4.0, 3 / 8.0, 1 / 4.0, 1 / 16.0}, bi[3] = {0.25, 0.5, 0.25};
  double sw = 0, sv = 0, sc[3] = {0, 0, 0};
  const double inv = referenceInvBandwidth(s, lv, x, y);
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const int qx = x + dx * lv.step, qy = y + dy * lv.step;
      if (qx < 0 || qy < 0 || qx >= s.w || qy >= s.h) continue;
      const double hk = r == 2 ? b3[dx + 2] * b3[dy + 2] : bi[dx + 1] * bi[dy + 1];
      double wt = 1.0;
      if (dx || dy) {
        double dot = 0;
        for (int c = 0; c < 3; ++c) dot += double(s.guide.normal[c].at(x, y)) * s.guide.normal[c].at(qx, qy);
        const double wn = std::pow(std::max(0.0, dot), lv.normalExponent);
        const double g = double(s.guide.gradX.at(x, y)) * dx * lv.step + double(s.guide.gradY.at(x, y)) * dy * lv.step;
        const double zp = s.guide.depth.at(x, y), eps = lv.depthEpsilon + lv.depthEpsilonRelative * std::abs(zp);
        const double wz = std::exp(-std::abs(zp - s.guide.depth.at(qx, qy)) / (lv.sigmaDepth * std::abs(g) + eps));
        const double wl = std::exp(-std::abs(double(s.a.lum.at(x, y)) - s.a.lum.at(qx, qy)) * inv);
        wt = wn * wz * wl;
      }
      sw += hk * wt;
      sv += hk * hk * wt * wt * s.a.var.at(qx, qy);
      for (int c = 0; c < 3; ++c) sc[c] += hk * wt * s.a.color[c].at(qx, qy);
    }
  for (int c = 0; c < 3; ++c) out[c] = sc[c] / sw;
  var = sv / (sw * sw);
}

void randomScene(Scene& s, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int y = 0; y < s.h; ++y)
    for (int x = 0; x < s.w; ++x) {
      // Smooth-ish depth with a step, slightly varying normals, noisy colour.
      s.guide.depth.at(x, y) = (x < s.w / 2 ? 4.0f : 6.0f) + 0.01f * y + 0.02f * u(rng);
      s.guide.gradX.at(x, y) = 0.01f * (u(rng) - 0.5f);
      s.guide.gradY.at(x, y) = 0.01f;
      float n[3] = {0.2f * (u(rng) - 0.5f), 0.2f * (u(rng) - 0.5f), 1.0f};
      const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int c = 0; c < 3; ++c) s.guide.normal[c].at(x, y) = n[c] / len;
      for (int c = 0; c < 3; ++c) s.a.color[c].at(x, y) = u(rng);
      s.a.lum.at(x, y) = luminance(s.a.color[0].at(x, y), s.a.color[1].at(x, y), s.a.color[2].at(x, y));
      s.a.var.at(x, y) = 0.05f * u(rng);
      s.inv.at(x, y) = u(rng) < 0.1f ? 0.0f : 1.0f + 7.0f * u(rng);  // sigma_l multiplier, sometimes off
    }
}

// On every CPU path this machine runs (sse2: 4 lanes, avx2: 8, avx512: 16), forced in turn.
TEST(Atrous, MatchesDoublePrecisionReferenceBothKernels) {
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
  for (AtrousKernel k : {AtrousKernel::B3Spline5x5, AtrousKernel::Binomial3x3})
    for (int step : {1, 4}) {
      Scene s(37, 21, 8);  // width not a multiple of 8 or 16: the tail tile is exercised
      randomScene(s, 7 + step);
      AtrousLevel lv = level(k, step, &s.inv);
      lv.normalExponent = step == 1 ? 64 : 5;  // the unrolled and the generic power
      lv.varianceScale = k == AtrousKernel::Binomial3x3;  // Dundr's variance scale
      if (step == 4) lv.depthEpsilon = 0.0f, lv.depthEpsilonRelative = 2.5e-3f;  // the scale-free eps
      atrousLevel(s.guide, lv, s.a, s.b);
      for (int y = 0; y < s.h; ++y)
        for (int x = 0; x < s.w; ++x) {
          double ref[3], var;
          referencePixel(s, lv, x, y, ref, var);
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(s.b.color[c].at(x, y), ref[c], 2e-5) << x << "," << y << " " << cpuPathName(path);
          ASSERT_NEAR(s.b.var.at(x, y), var, 2e-6 + 1e-4 * var) << x << "," << y << " " << cpuPathName(path);
          ASSERT_NEAR(s.b.lum.at(x, y), luminance(s.b.color[0].at(x, y), s.b.color[1].at(x, y), s.b.color[2].at(x, y)), 1e-6);
        }
    }
  }
}

// AtrousLevel::remodulatedOut (SVGF's sum and remodulation fused into the last level): the
// level's colour times the albedo factor (albedo below kAlbedoEpsilon counts as 1), bit for
// bit the separate pass's product, at every pixel of a width that leaves a tail on each path
// (37 = 2 x 16 + 5), masked and dense, with and without albedo.
TEST(Atrous, RemodulatedLastLevelIsTheLevelTimesTheAlbedoOnEveryPath) {
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    for (bool masked : {false, true})
      for (bool withAlbedo : {true, false}) {
        Scene s(37, 21, 8);
        randomScene(s, 11);
        PaddedPlane validIn, validOut;
        validIn.resize(s.w, s.h, 8);
        validOut.resize(s.w, s.h, 8);
        std::vector<Plane> albedo(3, Plane(s.w, s.h));
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        for (int y = 0; y < s.h; ++y)
          for (int x = 0; x < s.w; ++x) {
            validIn.at(x, y) = (x * 7 + y * 3) % 5 ? 1.0f : 0.0f;
            for (int c = 0; c < 3; ++c) {
              const float r = u(rng);
              albedo[c](x, y) = r < 0.2f ? 0.0f : r < 0.3f ? 5e-4f : r;  // black and dark ones count as 1
            }
          }
        AtrousLevel lv = level(AtrousKernel::B3Spline5x5, 2, &s.inv);
        lv.propagateVariance = false;  // as a last level
        if (masked) lv.validIn = &validIn, lv.validOut = &validOut;
        atrousLevel(s.guide, lv, s.a, s.b);  // the plain level
        Plane3 out;
        resize(out, s.w, s.h, -1.0f);
        lv.remodulatedOut = &out;
        lv.remodulateAlbedo = withAlbedo ? &albedo : nullptr;
        AtrousImage other;
        other.resize(s.w, s.h, 8);
        atrousLevel(s.guide, lv, s.a, other);
        for (int y = 0; y < s.h; ++y)
          for (int x = 0; x < s.w; ++x)
            for (int c = 0; c < 3; ++c) {
              const float a = albedo[c](x, y);
              const float expected = withAlbedo ? s.b.color[c].at(x, y) * (a > 1e-3f ? a : 1.0f) : s.b.color[c].at(x, y);
              ASSERT_EQ(out[c](x, y), expected) << x << "," << y << " " << cpuPathName(path) << " masked " << masked;
            }
      }
  }
}

TEST(Atrous, ConstantImageIsAFixedPoint) {
  Scene s(53, 29, 32);
  randomScene(s, 3);  // arbitrary features and variance, constant colour
  for (int y = 0; y < s.h; ++y)
    for (int x = 0; x < s.w; ++x) {
      s.a.color[0].at(x, y) = 0.7f;
      s.a.color[1].at(x, y) = 0.2f;
      s.a.color[2].at(x, y) = 1.5f;
      s.a.lum.at(x, y) = luminance(0.7f, 0.2f, 1.5f);
    }
  for (int step : {1, 2, 4, 8, 16}) {
    atrousLevel(s.guide, level(AtrousKernel::B3Spline5x5, step, &s.inv), s.a, s.b);
    for (int y = 0; y < s.h; ++y)
      for (int x = 0; x < s.w; ++x) {
        ASSERT_NEAR(s.b.color[0].at(x, y), 0.7f, 1e-6);
        ASSERT_NEAR(s.b.color[1].at(x, y), 0.2f, 1e-6);
        ASSERT_NEAR(s.b.color[2].at(x, y), 1.5f, 2e-6);
      }
  }
}

// Five levels of the filter, ping-ponging between the two images; returns the final one.
AtrousImage& runLevels(Scene& s, AtrousKernel k, int levels) {
  AtrousImage* src = &s.a;
  AtrousImage* dst = &s.b;
  for (int i = 0; i < levels; ++i) {
    AtrousLevel lv = level(k, 1 << i, &s.inv);
    atrousLevel(s.guide, lv, *src, *dst);
    std::swap(src, dst);
  }
  return *src;
}

TEST(Atrous, DepthAndNormalEdgesSurviveFiveLevels) {
  Scene s(64, 48, 32);
  s.flat();
  // Left half: depth 5, colour 1; right half: depth 9 (a depth edge), colour 0. Bottom
  // quarter of the right half: depth 9 but a normal turned 90 degrees, colour 0.5.
  for (int y = 0; y < s.h; ++y)
    for (int x = 0; x < s.w; ++x) {
      const bool right = x >= 32, bottom = y >= 36;
      s.guide.depth.at(x, y) = right ? 9.0f : 5.0f;
      if (right && bottom) {
        s.guide.normal[2].at(x, y) = 0.0f;
        s.guide.normal[1].at(x, y) = 1.0f;
      }
      const float v = !right ? 1.0f : bottom ? 0.5f : 0.0f;
      for (int c = 0; c < 3; ++c) s.a.color[c].at(x, y) = v;
      s.a.lum.at(x, y) = v;
      s.a.var.at(x, y) = 1.0f;
      s.inv.at(x, y) = 0.0f;  // sigma_l scale 0: luminance weight off, only the features keep the edges
    }
  const AtrousImage& r = runLevels(s, AtrousKernel::B3Spline5x5, 5);
  for (int y = 0; y < s.h; ++y)
    for (int x = 0; x < s.w; ++x) {
      const bool right = x >= 32, bottom = y >= 36;
      const float v = !right ? 1.0f : bottom ? 0.5f : 0.0f;
      ASSERT_NEAR(r.color[0].at(x, y), v, 1e-4) << x << "," << y;
    }
}

TEST(Atrous, UnweightedImpulseResponseHasTheExpectedSupport) {
  // Flat features and w_l off: each level is a plain dilated kernel, so five levels are the
  // convolution of the dilated 1D kernels per axis: support radius r * (1+2+4+8+16).
  for (AtrousKernel k : {AtrousKernel::B3Spline5x5, AtrousKernel::Binomial3x3}) {
    const int r = kernelRadius(k), support = r * 31;
    // Every pixel of the support keeps all its taps inside the image (no renormalization).
    const int n = 2 * (support + r * 16) + 3;
    Scene s(n, n, 32);
    s.flat();
    const int c = n / 2;
    s.a.color[0].at(c, c) = 1.0f;
    const AtrousImage& out = runLevels(s, k, 5);
    // Independent 1D reference: convolve the dilated kernels in double.
    std::vector<double> line(size_t(n), 0.0);
    line[c] = 1.0;
    for (int i = 0; i < 5; ++i) {
      std::vector<double> next(size_t(n), 0.0);
      for (int x = 0; x < n; ++x)
        for (int d = -r; d <= r; ++d) {
          const int q = x + d * (1 << i);
          if (q >= 0 && q < n) next[x] += kernelWeight1D(k, d) * line[q];
        }
      line = next;
    }
    double total = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const float v = out.color[0].at(x, y);
        const bool inside = std::abs(x - c) <= support && std::abs(y - c) <= support;
        if (!inside) {
          ASSERT_EQ(v, 0.0f) << x << "," << y;
        }
        ASSERT_NEAR(v, line[x] * line[y], 1e-7) << x << "," << y;
        total += v;
      }
    EXPECT_GT(out.color[0].at(c + support, c), 0.0f);  // the support's corner taps are reached
    EXPECT_GT(out.color[0].at(c - support, c - support), 0.0f);
    EXPECT_NEAR(total, 1.0, 1e-5);
  }
}

TEST(Atrous, VariancePropagationOfAnUnweightedLevel) {
  // With all weights 1 and constant variance V, Eq. 4 gives V * sum h^2 (5x5 B3: (35/128)^2).
  Scene s(40, 40, 32);
  s.flat();
  for (int y = 0; y < s.h; ++y)
    for (int x = 0; x < s.w; ++x) s.a.var.at(x, y) = 2.0f;
  atrousLevel(s.guide, level(AtrousKernel::B3Spline5x5, 2, &s.inv), s.a, s.b);
  const double sumH2_1d = (1 + 16 + 36 + 16 + 1) / 256.0;  // (1/16)^2 + (1/4)^2 + (3/8)^2 + ...
  EXPECT_NEAR(s.b.var.at(20, 20), 2.0 * sumH2_1d * sumH2_1d, 1e-6);
}

TEST(Atrous, SparseInputSkipsMissingTapsAndFillsHoles) {
  Scene s(48, 32, 32);
  s.flat();
  PaddedPlane validIn, validOut;
  validIn.resize(s.w, s.h, 32);
  validOut.resize(s.w, s.h, 32);
  for (int y = 0; y < s.h; ++y)
    for (int x = 0; x < s.w; ++x) {
      // Left part valid with colour 0.25 except one hole; right of x = 30 all missing, with
      // garbage colour that must not leak.
      const bool valid = x < 30 && !(x == 10 && y == 10);
      validIn.at(x, y) = valid ? 1.0f : 0.0f;
      for (int c = 0; c < 3; ++c) s.a.color[c].at(x, y) = valid ? 0.25f : 100.0f;
      s.a.lum.at(x, y) = valid ? 0.25f : 100.0f;
    }
  AtrousLevel lv = level(AtrousKernel::B3Spline5x5, 1, &s.inv);
  lv.validIn = &validIn;
  lv.validOut = &validOut;
  atrousLevel(s.guide, lv, s.a, s.b);
  EXPECT_NEAR(s.b.color[0].at(10, 10), 0.25f, 1e-6);  // the hole is filled from its neighbours
  EXPECT_EQ(validOut.at(10, 10), 1.0f);
  EXPECT_NEAR(s.b.color[1].at(29, 5), 0.25f, 1e-6);   // no garbage from the missing side
  EXPECT_NEAR(s.b.color[2].at(31, 5), 0.25f, 1e-6);   // a missing pixel next to data is filled
  EXPECT_EQ(validOut.at(31, 5), 1.0f);
  EXPECT_EQ(s.b.color[0].at(40, 5), 0.0f);            // nothing within reach: stays missing
  EXPECT_EQ(validOut.at(40, 5), 0.0f);
}

TEST(SvgfProgressive, UnsampledPixelsKeepTheirHistory) {
  const int w = 8, h = 8;
  Reprojection rp;
  rp.resize(w, h);
  TemporalAccumulator acc;
  acc.resize(w, h);
  Plane3 frame;
  resize(frame, w, h, 0.4f);
  Plane mask(w, h, 1.0f);
  AccumulationOptions opt;
  opt.sampleMask = &mask;
  mask(2, 2) = 0.0f;  // never sampled in the first frame: missing
  acc.run(rp, frame, 0.2f, 0.2f, 255, opt);
  EXPECT_EQ(acc.historyLength()(2, 2), 0.0f);
  EXPECT_EQ(acc.color()[0](2, 2), 0.0f);
  for (int i = 0; i < w * h; ++i) {  // identity reprojection
    rp.kind[i] = Reprojection::Bilinear;
    rp.base[i] = i;
    rp.weights[i] = {1, 0, 0, 0};
  }
  for (auto& c : frame) c.fill(0.8f);
  mask.fill(1.0f);
  mask(5, 5) = 0.0f;  // unsampled now: keeps 0.4, length 1, moments of 0.4
  acc.run(rp, frame, 0.2f, 0.2f, 255, opt);
  EXPECT_FLOAT_EQ(acc.color()[0](5, 5), 0.4f);
  EXPECT_EQ(acc.historyLength()(5, 5), 1.0f);
  EXPECT_NEAR(acc.moment1()(5, 5), 0.4f, 1e-6);
  EXPECT_NEAR(acc.color()[0](4, 5), 0.6f, 1e-6);  // sampled: mean of 0.4 and 0.8
  EXPECT_EQ(acc.historyLength()(4, 5), 2.0f);
  EXPECT_NEAR(acc.color()[0](2, 2), 0.8f, 1e-6);  // first sample of the missing pixel
  EXPECT_EQ(acc.historyLength()(2, 2), 1.0f);
}

// ---------------------------------------------------------------- variance estimate

// Filter::varianceRows run as the accumulation's afterRows (svgf.cpp) gives the levels exactly
// what the variance pass computes afterwards from the same planes: three frames of noise with
// an identity reprojection where every fifth pixel has no history (short histories: the
// spatial estimate runs too), compared bit for bit with a second filter and accumulator
// without the hook.
TEST(SvgfFilter, VarianceRowsAfterTheAccumulationEqualTheVariancePass) {
  const int w = 37, h = 23;
  const svgf::FilterParams p = svgf::filterParams(SvgfSettings{}, false);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Plane z(w, h);
  std::vector<Plane> n(3, Plane(w, h));
  for (int i = 0; i < w * h; ++i) {
    z.data[size_t(i)] = 2.0f + 0.01f * float(i % w);
    n[2].data[size_t(i)] = 1.0f;
  }
  AtrousGuide g;
  g.resize(w, h, p.requiredPad());
  g.build(z, n, nullptr, 0.0f);
  Reprojection rp;
  rp.resize(w, h);
  TemporalAccumulator accFused, accPlain;
  accFused.resize(w, h);
  accPlain.resize(w, h);
  svgf::Filter fused, plain;
  fused.resize(w, h, p.requiredPad());
  plain.resize(w, h, p.requiredPad());
  Plane3 frame, currentFused, currentPlain;
  resize(frame, w, h);
  resize(currentFused, w, h);
  resize(currentPlain, w, h);
  for (int f = 0; f < 3; ++f) {
    for (auto& c : frame)
      for (float& v : c.data) v = u(rng);
    AccumulationOptions withRows, without;
    withRows.current = &currentFused;
    without.current = &currentPlain;
    std::atomic<size_t> shortCount{0};
    withRows.afterRows = [&](int rowBegin, int rowEnd) {
      shortCount += fused.varianceRows(accFused, currentFused, p, rowBegin, rowEnd);
    };
    accFused.run(rp, frame, 0.2f, 0.2f, 32, withRows);
    accPlain.run(rp, frame, 0.2f, 0.2f, 32, without);
    FrameStats stats;
    const size_t rowsShortCount = shortCount;
    svgf::FilterExtras extras;
    extras.varianceRowsShortCount = &rowsShortCount;
    const AtrousImage& a = fused.run(g, accFused, currentFused, nullptr, p, stats, "", extras);
    const AtrousImage& b = plain.run(g, accPlain, currentPlain, nullptr, p, stats);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        for (int c = 0; c < 3; ++c) ASSERT_EQ(a.color[c].at(x, y), b.color[c].at(x, y)) << f << " " << x << "," << y;
        ASSERT_EQ(a.var.at(x, y), b.var.at(x, y)) << f << " " << x << "," << y;
      }
    for (int i = 0; i < w * h; ++i) {  // identity from now on, every fifth pixel without history
      rp.kind[size_t(i)] = i % 5 ? Reprojection::Bilinear : Reprojection::None;
      rp.base[size_t(i)] = i;
      rp.weights[size_t(i)] = {i % 5 ? 1.0f : 0.0f, 0, 0, 0};
    }
  }
}

TEST(SvgfVariance, SpatialEstimateExactlyWhenHistoryIsShort) {
  const int w = 24, h = 16;
  AtrousGuide g;
  g.resize(w, h, 8);
  AtrousImage out;
  out.resize(w, h, 8);
  PaddedPlane scratch[2];
  for (auto& p : scratch) p.resize(w, h, 8);
  Plane len(w, h), m1(w, h), m2(w, h);
  Plane3 cur, acc;
  resize(cur, w, h);
  resize(acc, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      g.depth.at(x, y) = 5.0f;
      g.normal[2].at(x, y) = 1.0f;
      len(x, y) = float(1 + (x + y) % 6);       // 1..6: short where < 4
      m1(x, y) = 0.5f;
      m2(x, y) = 0.5f * 0.5f + 0.09f;           // temporal variance 0.09
      const float l = (x + y) % 2 ? 1.0f : 0.0f; // checkerboard: window variance ~0.25
      for (int c = 0; c < 3; ++c) cur[c](x, y) = l;
    }
  svgf::VarianceInputs in{&len, &m1, &m2, &cur, &acc};
  svgf::VarianceParams p;  // Schied: 7x7 from the current luminance, n < 4
  const size_t spatial = svgf::estimateVariance(g, in, p, out, scratch);
  size_t expectedSpatial = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (len(x, y) >= 4) {
        ASSERT_NEAR(out.var.at(x, y), 0.09f, 1e-6) << x << "," << y;
        continue;
      }
      ++expectedSpatial;
      // Flat features: uniform weights over the in-image part of the 7x7 window.
      double s1 = 0, s2 = 0, n = 0;
      for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const double l = (qx + qy) % 2 ? 1.0 : 0.0;
          s1 += l;
          s2 += l * l;
          n += 1;
        }
      ASSERT_NEAR(out.var.at(x, y), s2 / n - (s1 / n) * (s1 / n), 1e-6) << x << "," << y;
    }
  EXPECT_EQ(spatial, expectedSpatial);

  // Voorhuis: from the accumulated moments -> mean(m2) - mean(m1)^2 = 0.09 although the
  // current luminance is a checkerboard; and > 0 when the current frame is black.
  for (auto& c : cur) c.fill(0.0f);
  p.fromMoments = true;
  svgf::estimateVariance(g, in, p, out, scratch);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ASSERT_NEAR(out.var.at(x, y), 0.09f, 1e-6);
  // Current-luminance estimate of a black frame is 0 where the history is short.
  p.fromMoments = false;
  svgf::estimateVariance(g, in, p, out, scratch);
  EXPECT_EQ(out.var.at(0, 0), 0.0f);  // len(0,0) = 1
}

// The spatial estimate on varied features against a double-precision evaluation written from
// Schied Sec. 4.2 (weights w_z w_n, centre weight 1, taps outside the image left out), on every
// CPU path: radius 2, 3 (the unrolled window) and 4 (rows of nine opposite pairs, more than
// the seven the kernel takes at once), the series and the exact power of w_n, with and
// without mesh ids.
TEST(SvgfVariance, SpatialEstimateMatchesDoublePrecisionReferenceOnEveryPath) {
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    for (int radius : {2, 3, 4})
      for (int e : {64, 5})
        for (bool ids : {false, true}) {
          Scene s(37, 21, 8);  // width not a multiple of 8 or 16: the tail tile is exercised
          randomScene(s, uint32_t(11 * radius + e + ids));
          Plane len(s.w, s.h);
          PaddedPlane id, var;
          id.resize(s.w, s.h, 8);
          var.resize(s.w, s.h, 8);
          for (int y = 0; y < s.h; ++y)
            for (int x = 0; x < s.w; ++x) {
              len(x, y) = float(1 + (3 * x + y) % 5);  // short where < 4
              s.a.var.at(x, y) = s.a.lum.at(x, y) * s.a.lum.at(x, y) + 0.01f * s.a.color[1].at(x, y);  // "b"
              id.at(x, y) = (x / 5 + y / 4) % 3 == 0 ? 2.0f : 1.0f;
              var.at(x, y) = -1.0f;  // kept where the history is long
            }
          const float sigmaZ = 1.0f, epsZ = 1e-2f, epsRelZ = radius == 4 ? 2.5e-3f : 0.0f;
          spatialVariance(s.guide, s.a.lum, s.a.var, len, 4.0f, radius, sigmaZ, epsZ, epsRelZ, e, var, ids ? &id : nullptr);
          for (int y = 0; y < s.h; ++y)
            for (int x = 0; x < s.w; ++x) {
              if (len(x, y) >= 4) {
                ASSERT_EQ(var.at(x, y), -1.0f);
                continue;
              }
              double sw = 0, s1 = 0, s2 = 0;
              const double zp = s.guide.depth.at(x, y), eps = epsZ + epsRelZ * std::abs(zp);
              for (int dy = -radius; dy <= radius; ++dy)
                for (int dx = -radius; dx <= radius; ++dx) {
                  const int qx = x + dx, qy = y + dy;
                  if (qx < 0 || qy < 0 || qx >= s.w || qy >= s.h) continue;
                  double wt = 1.0;
                  if (dx || dy) {
                    double dot = 0;
                    for (int c = 0; c < 3; ++c) dot += double(s.guide.normal[c].at(x, y)) * s.guide.normal[c].at(qx, qy);
                    const double g = double(s.guide.gradX.at(x, y)) * dx + double(s.guide.gradY.at(x, y)) * dy;
                    wt = std::pow(std::max(0.0, dot), e) *
                         std::exp(-std::abs(zp - s.guide.depth.at(qx, qy)) / (sigmaZ * std::abs(g) + eps));
                    if (ids && id.at(qx, qy) != id.at(x, y)) wt = 0.0;
                  }
                  sw += wt;
                  s1 += wt * s.a.lum.at(qx, qy);
                  s2 += wt * s.a.var.at(qx, qy);
                }
              const double ref = std::max(0.0, s2 / sw - (s1 / sw) * (s1 / sw));
              ASSERT_NEAR(var.at(x, y), ref, 2e-5 + 1e-4 * ref)
                  << x << "," << y << " radius " << radius << " e " << e << " ids " << ids << " " << cpuPathName(path);
            }
        }
  }
}

// A static camera over one pixel value sequence: the moments must be exact averages for
// short histories with momentsTrueAverage, and an EMA without.
TEST(SvgfVariance, MomentsExactForShortHistories) {
  const int w = 8, h = 8;
  Reprojection rp;
  rp.resize(w, h);
  TemporalAccumulator acc;
  acc.resize(w, h);
  Plane3 frame;
  resize(frame, w, h);
  const float xs[4] = {0.2f, 1.0f, 0.4f, 0.8f};
  for (bool cumulative : {true, false}) {
    acc.reset();
    std::fill(rp.kind.begin(), rp.kind.end(), Reprojection::None);
    double m1 = 0, m2 = 0;
    for (int t = 0; t < 4; ++t) {
      for (auto& c : frame) c.fill(xs[t]);  // grey: luminance = value
      AccumulationOptions opt;
      opt.cumulativeMoments = cumulative;
      acc.run(rp, frame, 0.2f, 0.2f, 255, opt);
      // Identity reprojection from the second frame on.
      for (int i = 0; i < w * h; ++i) {
        rp.kind[i] = Reprojection::Bilinear;
        rp.base[i] = i;
        rp.weights[i] = {1, 0, 0, 0};
      }
      const double a = cumulative ? 1.0 / (t + 1) : (t == 0 ? 1.0 : 0.2);
      m1 = a * xs[t] + (1 - a) * m1;
      m2 = a * xs[t] * xs[t] + (1 - a) * m2;
    }
    if (cumulative) {
      // Plain means of the four values: 0.6 and (0.04 + 1 + 0.16 + 0.64) / 4 = 0.46.
      EXPECT_NEAR(m1, 0.6, 1e-7);
      EXPECT_NEAR(m2, 0.46, 1e-7);
    }
    EXPECT_NEAR(acc.moment1()(3, 3), m1, 1e-6);
    EXPECT_NEAR(acc.moment2()(3, 3), m2, 1e-6);
    EXPECT_NEAR(acc.temporalVariance(27), std::max(0.0, m2 - m1 * m1), 1e-6);
    EXPECT_EQ(acc.historyLength()(3, 3), 4.0f);
  }
}

// L*'s cube root against double precision's: within half a float ulp (to the nearest) over
// the range L* uses it on, at a million log-spaced and random points, and infinity stays.
TEST(SvgfVariance, CubeRootIsRoundedToNearest) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> logY(std::log(216.0 / 24389.0), std::log(1e30));
  for (int i = 0; i < 1000000; ++i) {
    const float y = i % 2 ? float(std::exp(logY(rng))) : float(216.0 / 24389.0 * std::pow(1.0001, i / 2));
    const double exact = std::cbrt(double(y));
    const double ulp = std::nextafter(float(exact), INFINITY) - float(exact);
    ASSERT_LE(std::abs(double(cubeRoot(y)) - exact), 0.5001 * ulp) << y;
  }
  EXPECT_EQ(cubeRoot(INFINITY), INFINITY);
  EXPECT_EQ(cubeRoot(27.0f), 3.0f);
  EXPECT_EQ(cubeRoot(0.125f), 0.5f);
}

TEST(SvgfVariance, CieLightnessMoments) {
  EXPECT_NEAR(cieLightness(1.0f), 100.0f, 1e-4);
  EXPECT_NEAR(cieLightness(0.0f), 0.0f, 1e-5);
  EXPECT_NEAR(cieLightness(0.18f), 49.496f, 1e-2);  // middle grey
  EXPECT_NEAR(cieLightness(0.001f), 0.9033f, 1e-3);  // linear branch: 903.3 Y
}

// ---------------------------------------------------------------- other passes

TEST(SvgfPasses, MedianRemovesAFireflyOnDiffusePixelsOnly) {
  Plane3 in, out;
  resize(in, 9, 9, 0.5f);
  resize(out, 9, 9);
  for (auto& c : in) c(4, 4) = 100.0f;
  svgf::median3x3(in, nullptr, out);
  EXPECT_EQ(out[0](4, 4), 0.5f);
  Plane rough(9, 9, 1.0f);
  rough(4, 4) = 0.2f;  // glossy: kept
  svgf::median3x3(in, &rough, out);
  EXPECT_EQ(out[1](4, 4), 100.0f);
}

// Every pixel against the median of its nine edge-clamped neighbours found by sorting them, on
// random values with ties, at sizes down to one pixel; with roughness, glossy pixels pass.
TEST(SvgfPasses, MedianIsTheSortedMiddleOfTheClampedNeighbourhood) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> level(0, 40);  // few distinct values: ties
  for (auto [w, h] : {std::pair{1, 1}, {2, 3}, {5, 1}, {17, 9}}) {
    Plane3 in, out;
    resize(in, w, h);
    resize(out, w, h);
    Plane rough(w, h);
    for (auto& c : in)
      for (float& v : c.data) v = 0.25f * float(level(rng));
    for (float& v : rough.data) v = level(rng) < 10 ? 0.3f : 0.95f;
    for (const Plane* r : std::initializer_list<const Plane*>{nullptr, &rough}) {
      svgf::median3x3(in, r, out);
      for (int c = 0; c < 3; ++c)
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            std::vector<float> v;
            for (int j = -1; j <= 1; ++j)
              for (int i = -1; i <= 1; ++i) v.push_back(in[c](std::clamp(x + i, 0, w - 1), std::clamp(y + j, 0, h - 1)));
            std::sort(v.begin(), v.end());
            const float want = r && rough(x, y) < 0.9f ? in[c](x, y) : v[4];
            EXPECT_EQ(out[c](x, y), want) << w << "x" << h << " at " << x << "," << y << " channel " << c;
          }
    }
  }
}

TEST(SvgfPasses, LevelOrders) {
  int s[5];
  svgf::levelSteps(SvgfLevelOrder::fineToCoarse, 5, s);
  EXPECT_EQ(std::vector<int>(s, s + 5), (std::vector<int>{1, 2, 4, 8, 16}));
  svgf::levelSteps(SvgfLevelOrder::firstThenCoarseToFine, 5, s);
  EXPECT_EQ(std::vector<int>(s, s + 5), (std::vector<int>{1, 16, 8, 4, 2}));
  svgf::levelSteps(SvgfLevelOrder::coarseToFine, 5, s);
  EXPECT_EQ(std::vector<int>(s, s + 5), (std::vector<int>{16, 8, 4, 2, 1}));
}

// ---------------------------------------------------------------- settings

TEST(SvgfSettingsTest, VariantPresetsAndToggles) {
  auto device = Device::create();
  auto d = device->createDenoiser("svgf");
  d->set("variant", "dundr");
  auto s = d->getSettings<SvgfSettings>();
  EXPECT_EQ(s.kernel, SvgfKernel::binomial3x3);
  EXPECT_EQ(s.levelOrder, SvgfLevelOrder::firstThenCoarseToFine);
  EXPECT_EQ(s.luminanceScale, SvgfLuminanceScale::variance);
  EXPECT_EQ(s.shortHistory, SvgfShortHistory::disableLuminanceWeight);
  EXPECT_FLOAT_EQ(s.alphaColor, 0.1f);
  // Sec. 4.5: the TAA history reprojected as the reprojection phase does, bilinearly.
  EXPECT_EQ(s.taa.taaHistoryFilter, TaaHistoryFilter::bilinear);
  d->set("kernel", "5x5");  // a toggle after the preset overrides it alone
  s = d->getSettings<SvgfSettings>();
  EXPECT_EQ(s.kernel, SvgfKernel::b3spline5x5);
  EXPECT_EQ(s.levelOrder, SvgfLevelOrder::firstThenCoarseToFine);
  d->set("variant", "gersthofer");
  s = d->getSettings<SvgfSettings>();
  EXPECT_EQ(s.luminance, SvgfLuminance::cieLightness);
  EXPECT_EQ(s.feedbackLevel, 0);
  EXPECT_EQ(s.spatialVarianceRadius, 1);
  EXPECT_EQ(s.kernel, SvgfKernel::b3spline5x5);  // back to Schied's
  EXPECT_EQ(s.taa.taaHistoryFilter, TaaSettings{}.taaHistoryFilter);
  const auto v = SvgfSettings::forVariant(SvgfVariant::voorhuis);
  EXPECT_TRUE(v.momentsTrueAverage && v.spatialVarianceFromMoments && v.shortHistoryBandwidth && v.fireflyMedian);
  EXPECT_FALSE(v.indirectVarianceFiltering);
  EXPECT_FLOAT_EQ(v.sigmaNormal, 64.0f);
  EXPECT_FLOAT_EQ(v.sigmaLuminance, 5.0f);
  // voorhuis = the paper's whole method ("Ours"): reflections, clipping and per-class alpha on top.
  EXPECT_EQ(v.specularMotion, SvgfSpecularMotion::automatic);
  EXPECT_TRUE(v.preferLobes);
  for (SvgfPart p : {v.reflectedFeatures, v.glossyBandwidth, v.neighbourhoodClipping, v.materialAlpha})
    EXPECT_EQ(p, SvgfPart::automatic);
  // The robustness-only set keeps its own name; Base and NoSpecReproj are the paper's baselines.
  const auto r = SvgfSettings::forVariant(SvgfVariant::voorhuisRobustness);
  EXPECT_TRUE(r.momentsTrueAverage && r.fireflyMedian && !r.indirectVarianceFiltering);
  EXPECT_EQ(r.specularMotion, SvgfSpecularMotion::primary);
  EXPECT_EQ(r.neighbourhoodClipping, SvgfPart::off);
  const auto base = SvgfSettings::forVariant(SvgfVariant::voorhuisBase);
  EXPECT_FALSE(base.momentsTrueAverage || base.fireflyMedian || base.shortHistoryBandwidth);
  EXPECT_FLOAT_EQ(base.sigmaNormal, 64.0f);
  EXPECT_FLOAT_EQ(base.sigmaLuminance, 5.0f);
  EXPECT_EQ(base.specularMotion, SvgfSpecularMotion::primary);
  const auto nsr = SvgfSettings::forVariant(SvgfVariant::voorhuisNoSpecReproj);
  EXPECT_EQ(nsr.specularMotion, SvgfSpecularMotion::none);
  EXPECT_FLOAT_EQ(nsr.sigmaLuminance, 5.0f);
  d->set("variant", "voorhuis");
  d->set("variant", "schied");  // a preset resets every Voorhuis part
  s = d->getSettings<SvgfSettings>();
  EXPECT_EQ(s.specularMotion, SvgfSpecularMotion::primary);
  EXPECT_EQ(s.neighbourhoodClipping, SvgfPart::off);
  EXPECT_FALSE(s.preferLobes);
  EXPECT_THROW(d->set("variant", "nope"), Error);
}

// ---------------------------------------------------------------- end to end

double rmseRgb(const Image& a, const Image& b) {
  double s = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.at(x, y, c)) - b.at(x, y, c);
        s += d * d;
      }
  return std::sqrt(s / (3.0 * a.width * a.height));
}

bool allFiniteRgb(const Image& a) {
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(a.at(x, y, c))) return false;
  return true;
}

struct SeqRun {
  double rmse;
  Image last;
};

constexpr int kFrames = 12;

// Denoises kFrames frames of the synthetic scene; RMSE of the last output vs the reference.
SeqRun runSequence(Denoiser* d, const synthetic::Scene& scene, bool splitDirect = false) {
  Image ref, out(scene.width, scene.height, 3);
  for (int i = 0; i < kFrames; ++i) {
    Frame f = synthetic::makeFrame(scene, i, &ref);
    if (splitDirect) {  // Direct = Color, Indirect = 0: must equal filtering Color alone
      f[Buffer::Direct] = f[Buffer::Color];
      f[Buffer::Indirect] = Image(scene.width, scene.height, 3);
    }
    if (d) d->denoise(f.inputs(), out.view());
    else out = f[Buffer::Color];
  }
  return {rmseRgb(out, ref), out};
}

synthetic::Scene svgfScene() {
  synthetic::Scene s;
  s.width = 128;
  s.height = 72;
  return s;
}

TEST(SvgfEndToEnd, MuchCloserToReferenceThanInputAndAccumulation) {
  auto device = Device::create();
  const auto scene = svgfScene();
  const double input = runSequence(nullptr, scene).rmse;
  auto acc = device->createDenoiser("accumulate");
  const double accumulated = runSequence(acc.get(), scene).rmse;
  auto svgf = device->createDenoiser("svgf");
  const SeqRun r = runSequence(svgf.get(), scene);
  ASSERT_TRUE(allFiniteRgb(r.last));
  std::printf("RMSE after %d frames: input %.4f, accumulate %.4f, svgf %.4f\n", kFrames, input, accumulated, r.rmse);
  // Measured (128x72, 12 frames): input 0.678, accumulate 0.188, svgf 0.082, i.e. svgf is at
  // 0.12x the input and 0.44x plain accumulation; asserted with some room.
  EXPECT_LT(r.rmse, 0.25 * input);
  EXPECT_LT(r.rmse, 0.6 * accumulated);
}

TEST(SvgfEndToEnd, EachVariantRunsAndDiffers) {
  auto device = Device::create();
  const auto scene = svgfScene();
  auto base = device->createDenoiser("svgf");
  const SeqRun ref = runSequence(base.get(), scene);
  const double input = runSequence(nullptr, scene).rmse;
  for (const char* v : {"dundr", "gersthofer", "voorhuis"}) {
    auto d = device->createDenoiser("svgf");
    d->set("variant", v);
    const SeqRun r = runSequence(d.get(), scene);
    ASSERT_TRUE(allFiniteRgb(r.last)) << v;
    std::printf("variant %-10s RMSE %.4f (schied %.4f)\n", v, r.rmse, ref.rmse);
    // Measured: dundr 0.078, gersthofer 0.081, voorhuis 0.083 (input 0.678).
    EXPECT_LT(r.rmse, 0.4 * input) << v;
    EXPECT_GT(rmseRgb(r.last, ref.last), 1e-4) << v;  // differs from the default
  }
}

TEST(SvgfEndToEnd, SplitStreamWithZeroIndirectEqualsColorStream) {
  auto device = Device::create();
  const auto scene = svgfScene();
  auto a = device->createDenoiser("svgf");
  a->set("components", "color");
  auto b = device->createDenoiser("svgf");  // auto: Direct + Indirect found
  const SeqRun ra = runSequence(a.get(), scene, true), rb = runSequence(b.get(), scene, true);
  EXPECT_LT(rmseRgb(ra.last, rb.last), 1e-6);
  const auto names = [&] {
    std::vector<std::string> n;
    for (const auto& p : b->stats().passes) n.push_back(p.name);
    return n;
  }();
  EXPECT_NE(std::find(names.begin(), names.end(), "atrous1.indirect"), names.end());
}

// A stream's history is allocated when a frame first has the stream, the median's planes when
// it runs: one-stream input keeps one history (PlaneInspection), and a denoiser whose input
// gains the Direct / Indirect split mid-sequence then runs, after a reset, as a fresh one.
TEST(SvgfEndToEnd, AStreamsHistoryIsAllocatedWhenTheInputFirstHasIt) {
  const auto scene = svgfScene();
  const size_t plane = size_t(scene.width) * scene.height;
  auto frame = [&](int i, bool split) {
    Frame f = synthetic::makeFrame(scene, i);
    if (split) {  // 0.7 and 0.3 of the colour: two streams with different content
      f[Buffer::Direct] = f[Buffer::Indirect] = f[Buffer::Color];
      for (float& v : f[Buffer::Direct].pixels) v *= 0.7f;
      for (float& v : f[Buffer::Indirect].pixels) v *= 0.3f;
    }
    return f;
  };
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto gaining = device->createDenoiser("svgf");
  Image a(scene.width, scene.height, 3);
  for (int i = 0; i < 3; ++i) gaining->denoise(frame(i, false).inputs(), a.view());
  EXPECT_EQ(test::floatsKept(*gaining, "demodulated"), 3 * plane);
  EXPECT_EQ(test::floatsKept(*gaining, "history length"), 2 * plane);  // this frame's and the previous
  EXPECT_EQ(test::floatsKept(*gaining, "display"), 0u);
  EXPECT_EQ(test::floatsKept(*gaining, "diffuse lobe median"), 0u);
  gaining->reset();
  auto fresh = device->createDenoiser("svgf");
  test::expectRunsAsFresh(*gaining, *fresh, {frame(3, true), frame(4, true), frame(5, true)});
  EXPECT_EQ(test::floatsKept(*gaining, "demodulated"), 6 * plane);
  // The median's planes once it runs (fireflyMedian, the voorhuis preset's).
  gaining->set("fireflyMedian", "true");
  gaining->denoise(frame(6, false).inputs(), a.view());
  EXPECT_EQ(test::floatsKept(*gaining, "display"), 3 * plane);
}

// TAA's two history planes sets are allocated when TAA first runs: none while it is off, and a
// denoiser that switches it on mid-sequence then gives what one that had it from the start
// gives after a reset (the first TAA frame has no history in either).
TEST(SvgfEndToEnd, TaaHistoryIsAllocatedWhenTaaFirstRuns) {
  const auto scene = svgfScene();
  const size_t plane = size_t(scene.width) * scene.height;
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto switching = device->createDenoiser("svgf"), fresh = device->createDenoiser("svgf");
  switching->set("taa", "false");
  Image a(scene.width, scene.height, 3);
  for (int i = 0; i < 2; ++i) switching->denoise(synthetic::makeFrame(scene, i).inputs(), a.view());
  EXPECT_EQ(test::floatsKept(*switching, "taa history"), 0u);
  switching->set("taa", "true");
  switching->reset();
  test::expectRunsAsFresh(*switching, *fresh,
                          {synthetic::makeFrame(scene, 2), synthetic::makeFrame(scene, 3), synthetic::makeFrame(scene, 4)});
  EXPECT_EQ(test::floatsKept(*switching, "taa history"), 6 * plane);
}

// FrameStats::memory on the CPU: "frames" holds the imported buffers of this and the previous
// frame, "planes" the rest. Input gaining the Direct / Indirect split adds exactly two imported
// RGB buffers per frame kept (12 planes) and one stream's history (15 planes: demodulated
// colour 3, accumulated colour 2 x 3, both moments and the length 2 x 3).
TEST(SvgfEndToEnd, MemoryAccountingCountsTheSecondStreamsPlanes) {
  const auto scene = svgfScene();
  const uint64_t plane = uint64_t(scene.width) * scene.height * sizeof(float);
  auto memory = [](const Denoiser& d) {
    std::map<std::string, uint64_t> m;
    for (const MemoryUse& u : d.stats().memory) m[u.category] = u.bytes;
    return m;
  };
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto one = device->createDenoiser("svgf"), two = device->createDenoiser("svgf");
  Image out(scene.width, scene.height, 3);
  for (int i = 0; i < 2; ++i) {
    Frame f = synthetic::makeFrame(scene, i);
    one->denoise(f.inputs(), out.view());
    f[Buffer::Direct] = f[Buffer::Indirect] = f[Buffer::Color];
    for (float& v : f[Buffer::Indirect].pixels) v *= 0.5f;
    two->denoise(f.inputs(), out.view());
  }
  const auto a = memory(*one), b = memory(*two);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b.at("frames") - a.at("frames"), 12 * plane);
  EXPECT_EQ(b.at("planes") - a.at("planes"), 15 * plane);
}

// The filter's planes for settings that only some presets use (variancePrefilter = once,
// the short-history bandwidth's sigma scale) are allocated when those first run: plain SVGF
// keeps none, and switched on mid-sequence they give what a fresh denoiser with the same
// settings gives.
TEST(SvgfFilter, PlanesOfOptionalSettingsAreAllocatedWhenTheyFirstRun) {
  const auto scene = svgfScene();
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto switched = device->createDenoiser("svgf"), fresh = device->createDenoiser("svgf");
  Image a(scene.width, scene.height, 3);
  for (int i = 0; i < 3; ++i) switched->denoise(synthetic::makeFrame(scene, i).inputs(), a.view());
  for (const char* plane : {"prefiltered variance", "sigma scale", "valid"})
    EXPECT_EQ(test::floatsKept(*switched, plane), 0u) << plane << " kept by plain SVGF";
  for (Denoiser* d : {switched.get(), fresh.get()}) {
    d->set("variancePrefilter", "once");
    d->set("shortHistoryBandwidth", "true");
  }
  switched->reset();
  test::expectRunsAsFresh(*switched, *fresh,
                          {synthetic::makeFrame(scene, 3), synthetic::makeFrame(scene, 4), synthetic::makeFrame(scene, 5)});
  EXPECT_GT(test::floatsKept(*switched, "prefiltered variance"), size_t(scene.width) * scene.height);  // padded
  EXPECT_GT(test::floatsKept(*switched, "sigma scale"), size_t(scene.width) * scene.height);
}

// Issue 12 item 4: each preset filters the streams its paper describes, and a components
// setting given after the preset wins.
TEST(SvgfSettingsTest, PresetsChooseTheirPapersStreams) {
  EXPECT_EQ(SvgfSettings::forVariant(SvgfVariant::schied).components, SvgfComponents::automatic);  // direct + indirect
  EXPECT_EQ(SvgfSettings::forVariant(SvgfVariant::dundr).components, SvgfComponents::lobes);  // diffuse light, else colour
  EXPECT_EQ(SvgfSettings::forVariant(SvgfVariant::gersthofer).components, SvgfComponents::composite);  // one stream
  auto device = Device::create();
  auto d = device->createDenoiser("svgf");
  d->set("variant", "dundr");
  d->set("components", "diffuse");
  EXPECT_EQ(d->getSettings<SvgfSettings>().components, SvgfComponents::diffuse);
  d->set("variant", "gersthofer");  // a preset resets it again
  EXPECT_EQ(d->getSettings<SvgfSettings>().components, SvgfComponents::composite);
  // components = diffuse: the diffuse lobe filtered, the specular one not; the whole colour
  // without the split.
  svgf::StreamPlan plan[2];
  const auto all = [](Buffer) { return true; };
  ASSERT_EQ(svgf::planStreams(SvgfComponents::diffuse, all, plan), 2);
  EXPECT_EQ(plan[0].buffer, Buffer::Diffuse);
  EXPECT_TRUE(plan[0].filtered);
  EXPECT_EQ(plan[1].buffer, Buffer::Specular);
  EXPECT_FALSE(plan[1].filtered);
  ASSERT_EQ(svgf::planStreams(SvgfComponents::diffuse, [](Buffer b) { return b != Buffer::Specular; }, plan), 1);
  EXPECT_EQ(plan[0].buffer, Buffer::Color);
  // components = lobes (Dundr's): the diffuse and specular lobes, each filtered and demodulated
  // by its own colour pass where the frame has one (Blender's DiffCol / GlossCol), over
  // Direct + Indirect; the colour divided by the albedo where the frame has no lobes.
  ASSERT_EQ(svgf::planStreams(SvgfComponents::lobes, all, plan), 2);
  EXPECT_EQ(plan[0].buffer, Buffer::Diffuse);
  EXPECT_EQ(plan[0].albedo, Buffer::DiffuseAlbedo);
  EXPECT_EQ(plan[1].buffer, Buffer::Specular);
  EXPECT_EQ(plan[1].albedo, Buffer::SpecularAlbedo);
  EXPECT_TRUE(plan[0].filtered && plan[1].filtered);
  ASSERT_EQ(svgf::planStreams(SvgfComponents::lobes, [](Buffer b) { return b != Buffer::Diffuse; }, plan), 1);
  EXPECT_EQ(plan[0].buffer, Buffer::Color);
  EXPECT_TRUE(plan[0].demodulated);
}

// components = diffuse (dundr preset otherwise) on a frame split into diffuse = colour and a
// specular lobe S: the output is the colour-only output plus S exactly (S is neither
// accumulated nor filtered; TAA off, which is not additive).
TEST(SvgfEndToEnd, DiffuseComponentAddsTheSpecularLobeUnfiltered) {
  auto device = Device::create();
  const auto scene = svgfScene();
  Image out[2] = {Image(scene.width, scene.height, 3), Image(scene.width, scene.height, 3)};
  Image specular(scene.width, scene.height, 3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 2.0f);
  for (int k = 0; k < 2; ++k) {
    auto d = device->createDenoiser("svgf");
    d->set("variant", "dundr");
    d->set("components", "diffuse");
    d->set("taa", "false");
    for (int i = 0; i < 4; ++i) {
      Frame f = synthetic::makeFrame(scene, i);
      if (k == 1) {
        for (float& v : specular.pixels) v = u(rng);  // noisy: filtering would change it
        f[Buffer::Diffuse] = f[Buffer::Color];
        f[Buffer::Specular] = specular;
        for (size_t j = 0; j < specular.pixels.size(); ++j) f[Buffer::Color].pixels[j] += specular.pixels[j];
      }
      d->denoise(f.inputs(), out[k].view());
    }
  }
  double worst = 0;
  for (size_t j = 0; j < specular.pixels.size(); ++j)
    worst = std::max(worst, std::abs(double(out[1].pixels[j]) - out[0].pixels[j] - specular.pixels[j]));
  EXPECT_LT(worst, 1e-4);
}

TEST(SvgfEndToEnd, ProgressiveQuarterSampleRate) {
  // Dundr Sec. 5: each frame traces a random quarter of the pixels; the rest are empty.
  auto device = Device::create();
  auto d = device->createDenoiser("svgf");
  d->set("variant", "dundr");
  auto scene = svgfScene();
  scene.cameraSpeed = 0.0f;  // progressive rendering of a still view
  Image ref, out(scene.width, scene.height, 3), sparse;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 16; ++i) {
    Frame f = synthetic::makeFrame(scene, i, &ref);
    Image mask(scene.width, scene.height, 1);
    for (int y = 0; y < scene.height; ++y)
      for (int x = 0; x < scene.width; ++x) {
        const bool traced = u(rng) < 0.25f;
        mask.at(x, y) = traced ? 1.0f : 0.0f;
        if (!traced)
          for (int c = 0; c < 3; ++c) f[Buffer::Color].at(x, y, c) = 0.0f;
      }
    f[Buffer::SampleMask] = mask;
    d->denoise(f.inputs(), out.view());
    if (i == 0) sparse = f[Buffer::Color];
  }
  ASSERT_TRUE(allFiniteRgb(out));
  const double first = rmseRgb(sparse, ref), result = rmseRgb(out, ref);
  std::printf("progressive 1/4 spp: RMSE sparse frame %.4f, svgf after 16 frames %.4f\n", first, result);
  // Measured: 0.704 for one sparse frame, 0.050 after 16 frames (0.07x).
  EXPECT_LT(result, 0.15 * first);
  int empty = 0;  // every pixel has a value after the hole filling
  for (int y = 0; y < scene.height; ++y)
    for (int x = 0; x < scene.width; ++x) empty += out.at(x, y, 0) == 0.0f && out.at(x, y, 1) == 0.0f;
  EXPECT_EQ(empty, 0);
}

// A sample mask of ones (what the renderer writes at 1 spp) is the plain pipeline: the same
// output bit for bit as without the buffer, for Schied's and Dundr's settings. One unsampled
// pixel in one frame turns progressive mode on for that frame: the output changes.
TEST(SvgfEndToEnd, SampleMaskOfOnesIsThePlainPipeline) {
  auto device = Device::create();
  const auto scene = svgfScene();
  for (const char* variant : {"schied", "dundr"}) {
    SCOPED_TRACE(variant);
    auto run = [&](int maskMode) {  // 0: no mask buffer, 1: ones, 2: ones but one hole in frame 3
      auto d = device->createDenoiser("svgf");
      d->set("variant", variant);
      Image out(scene.width, scene.height, 3);
      std::vector<Image> outs;
      for (int i = 0; i < 5; ++i) {
        Frame f = synthetic::makeFrame(scene, i);
        if (maskMode > 0) {
          Image mask(scene.width, scene.height, 1, 1.0f);
          if (maskMode == 2 && i == 3) {
            mask.at(20, 10) = 0.0f;
            for (int c = 0; c < 3; ++c) f[Buffer::Color].at(20, 10, c) = 0.0f;
          }
          f[Buffer::SampleMask] = mask;
        }
        d->denoise(f.inputs(), out.view());
        outs.push_back(out);
      }
      return outs;
    };
    const std::vector<Image> plain = run(0), ones = run(1), hole = run(2);
    for (int i = 0; i < 5; ++i) EXPECT_EQ(plain[size_t(i)].pixels, ones[size_t(i)].pixels) << "frame " << i;
    EXPECT_EQ(plain[2].pixels, hole[2].pixels);
    EXPECT_NE(plain[3].pixels, hole[3].pixels);
  }
}

TEST(SvgfEndToEnd, MissingSplitBufferIsAnError) {
  auto device = Device::create();
  auto d = device->createDenoiser("svgf");
  d->set("components", "diffuseSpecular");
  auto scene = svgfScene();
  Frame f = synthetic::makeFrame(scene, 0);
  Image out(scene.width, scene.height, 3);
  EXPECT_THROW(d->denoise(f.inputs(), out.view()), Error);
}

}  // namespace
}  // namespace rtd
