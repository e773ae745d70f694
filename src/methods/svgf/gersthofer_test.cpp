// Gersthofer's VR pipeline (svgf, components = composite; docs/methods/stereo.md): the items
// of the note's checklist (shared/notes/vr-stereo-gersthofer.md Sec. 8) that the library
// implements, each against what the thesis says, plus the two-view API around it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/stereo_pair.h"
#include "methods/svgf/gersthofer.h"
#include "methods/svgf/svgf_passes.h"
#include "passes/atrous.h"
#include "passes/fxaa.h"
#include "passes/tonemap.h"
#include "rtd/rtd.h"
#include "synthetic/synthetic.h"
#include "support/test_frames.h"

namespace rtd {
namespace {

using svgf::boostDisoccluded;
using svgf::sampleCoverage;

// ---------------------------------------------------------------- helpers

synthetic::Scene tinyScene(float speed = 0.02f) {
  synthetic::Scene s;
  s.width = 48;
  s.height = 32;
  s.cameraSpeed = speed;
  return s;
}

// A synthetic frame with Gersthofer's split: indirect diffuse = `share` of the colour.
Frame splitFrame(const synthetic::Scene& scene, int i, float share = 0.4f, Image* ref = nullptr) {
  Frame f = synthetic::makeFrame(scene, i, ref);
  f[Buffer::IndirectDiffuse] = f[Buffer::Color];
  for (auto& v : f[Buffer::IndirectDiffuse].pixels) v *= share;
  return f;
}

SvgfSettings gersthofer() { return SvgfSettings::forVariant(SvgfVariant::gersthofer); }

double maxAbsDiff(const Image& a, const Image& b) {
  double m = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) m = std::max(m, double(std::abs(a.pixels[i] - b.pixels[i])));
  return m;
}

double mean(const Image& a, int channel = 1) {
  double s = 0;
  for (int i = 0; i < a.width * a.height; ++i) s += a.pixels[size_t(i) * a.channels + channel];
  return s / (a.width * a.height);
}

std::vector<std::string> passNames(const FrameStats& st) {
  std::vector<std::string> n;
  for (const auto& p : st.passes) n.push_back(p.name);
  return n;
}
bool hasPass(const FrameStats& st, const std::string& name) {
  const auto n = passNames(st);
  return std::find(n.begin(), n.end(), name) != n.end();
}

// ---------------------------------------------------------------- settings (checklist 14, 17, 18, 25)

TEST(GersthoferSettings, PresetHoldsTheThesisDefaults) {
  const SvgfSettings s = gersthofer();
  EXPECT_EQ(s.components, SvgfComponents::composite);
  EXPECT_TRUE(s.fixedAlpha);
  EXPECT_FLOAT_EQ(s.alphaColor, 0.2f);  // "alpha = 0.2"
  EXPECT_TRUE(s.maskBoost && s.indirectDiffuseMedian && s.eyeReprojection && s.glossyWeights);
  EXPECT_TRUE(s.spatialVarianceObjectId);
  EXPECT_EQ(s.spatialVarianceRadius, 1);  // 3x3
  EXPECT_EQ(s.shortHistoryFrames, 4);     // "< 4"
  EXPECT_EQ(s.luminance, SvgfLuminance::cieLightness);
  EXPECT_EQ(s.atrousIterations, 5);
  EXPECT_EQ(s.feedbackLevel, 0);  // history = temporal output
  EXPECT_TRUE(s.fxaa);
  EXPECT_FALSE(s.taa.taa);
  EXPECT_EQ(s.toneMap, SvgfToneMap::none);  // ACES is an option (the library's output is linear)
  // Another preset turns them all off again.
  const SvgfSettings b = SvgfSettings::forVariant(SvgfVariant::schied);
  EXPECT_EQ(b.components, SvgfComponents::automatic);
  EXPECT_FALSE(b.fixedAlpha || b.maskBoost || b.indirectDiffuseMedian || b.eyeReprojection || b.glossyWeights || b.fxaa);
  EXPECT_TRUE(b.taa.taa);
  // By name, as the CLI sets them.
  auto d = Device::create()->createStereoDenoiser("svgf");
  d->set("variant", "gersthofer");
  d->set("eyeReprojection", "false");
  EXPECT_FALSE(d->getSettings<SvgfSettings>().eyeReprojection);
  EXPECT_EQ(d->getSettings<SvgfSettings>().components, SvgfComponents::composite);
}

// ---------------------------------------------------------------- weights (checklist 24)

TEST(GersthoferWeights, GlossyWeightsOnHandValues) {
  EXPECT_FLOAT_EQ(roughnessWeight(0.0f), 0.01f);
  EXPECT_FLOAT_EQ(roughnessWeight(0.25f), 0.51f);
  EXPECT_FLOAT_EQ(roughnessWeight(1.0f), 1.01f);
  // |2 - 3| (1 - 0.5) / (sqrt(0.04) + 0) = 2.5 -> e^-2.5
  EXPECT_NEAR(indirectDistanceWeight(2.0f, 3.0f, 0.5f, 0.04f, 0.0f), 0.0820849986, 1e-7);
  // Mirror-like (roughness 0): the full distance difference counts: 1 / 0.2 -> e^-5
  EXPECT_NEAR(indirectDistanceWeight(2.0f, 3.0f, 0.0f, 0.04f, 0.0f), 0.0067379470, 1e-8);
  // w_zi -> 1 for roughness 1, whatever the distances.
  EXPECT_FLOAT_EQ(indirectDistanceWeight(1.0f, 50.0f, 1.0f, 1e-6f, 1e-10f), 1.0f);
}

// Double-precision a-trous level with Gersthofer's weights, written from Eq. 2.20 and 3.2.
struct GlossyScene {
  int w = 29, h = 19;
  AtrousGuide guide;
  AtrousImage in, out;
  PaddedPlane zi, ziScale, centre;
  explicit GlossyScene(uint32_t seed) {
    const int pad = 8;
    guide.resize(w, h, pad);
    in.resize(w, h, pad);
    out.resize(w, h, pad);
    for (PaddedPlane* p : {&zi, &ziScale, &centre}) p->resize(w, h, pad);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        guide.depth.at(x, y) = 3.0f + 0.01f * x;
        guide.gradX.at(x, y) = 0.01f;
        guide.gradY.at(x, y) = 0.0f;
        guide.normal[2].at(x, y) = 1.0f;
        for (int c = 0; c < 3; ++c) in.color[c].at(x, y) = u(rng);
        in.lum.at(x, y) = luminance(in.color[0].at(x, y), in.color[1].at(x, y), in.color[2].at(x, y));
        in.var.at(x, y) = 0.02f + 0.05f * u(rng);
        const float r = u(rng);
        zi.at(x, y) = (x < w / 2 ? 1.0f : 4.0f) + 0.3f * u(rng);  // a depth edge seen in the reflection
        ziScale.at(x, y) = 1.0f - r;
        centre.at(x, y) = u(rng) < 0.5f ? 1.0f / roughnessWeight(r) : 1.0f;
      }
  }
  void reference(const AtrousLevel& lv, int x, int y, double o[3]) const {
    const double b3[5] = {1 / 16.0, 1 / 4.0, 3 / 8.0, 1 / 4.0, 1 / 16.0};
    double v = 0;  // g3x3 of the variance, zero outside
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int qx = x + dx, qy = y + dy;
        if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
        v += (dx ? 0.5 : 1.0) * (dy ? 0.5 : 1.0) * 0.25 * in.var.at(qx, qy);
      }
    const double sd = std::sqrt(v);
    const double wr = 1.0 / centre.at(x, y);  // w_r on the neighbours
    double sw = 0, sc[3] = {0, 0, 0};
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int qx = x + dx * lv.step, qy = y + dy * lv.step;
        if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
        const double hk = b3[dx + 2] * b3[dy + 2];
        double wt = 1.0;
        if (dx || dy) {
          const double g = 0.01 * dx * lv.step;
          const double zp = guide.depth.at(x, y), eps = lv.depthEpsilon + lv.depthEpsilonRelative * std::abs(zp);
          const double wz = std::exp(-std::abs(zp - guide.depth.at(qx, qy)) / (lv.sigmaDepth * std::abs(g) + eps));
          const double wl = std::exp(-std::abs(double(in.lum.at(x, y)) - in.lum.at(qx, qy)) /
                                     (lv.sigmaLuminance * sd + lv.luminanceEpsilon));
          const double wzi = std::exp(-std::abs(double(zi.at(x, y)) - zi.at(qx, qy)) * ziScale.at(x, y) /
                                      (sd + lv.luminanceEpsilon));
          wt = wz * wl * wzi * wr;  // w_n = 1 (flat normals)
        }
        sw += hk * wt;
        for (int c = 0; c < 3; ++c) sc[c] += hk * wt * in.color[c].at(qx, qy);
      }
    for (int c = 0; c < 3; ++c) o[c] = sc[c] / sw;
  }
};

TEST(GersthoferWeights, FilterLevelMatchesDoublePrecisionReference) {
  for (int step : {1, 2}) {
    GlossyScene s(5 + step);
    AtrousLevel lv;
    lv.step = step;
    lv.normalExponent = 128;
    lv.luminanceEpsilon = 1e-4f;
    lv.propagateVariance = false;
    lv.indirectDistance = &s.zi;
    lv.indirectDistanceScale = &s.ziScale;
    lv.centreScale = &s.centre;
    atrousLevel(s.guide, lv, s.in, s.out);
    for (int y = 0; y < s.h; ++y)
      for (int x = 0; x < s.w; ++x) {
        double ref[3];
        s.reference(lv, x, y, ref);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(s.out.color[c].at(x, y), ref[c], 3e-5) << x << "," << y << " step " << step;
      }
  }
}

TEST(GersthoferWeights, ReflectedEdgeKeptOnGlossyPixelsBlurredOnRough) {
  // A mirror-like floor reflecting a depth edge: the colour and z_i step at x = 16. With the
  // glossy weights a roughness-0 pixel next to the edge keeps its side's colour; roughness 1
  // turns w_zi off and w_r to ~1, so the edge blurs as without them.
  auto contrast = [](float roughness, bool glossy) {
    const int w = 32, h = 8, pad = 8;
    AtrousGuide g;
    g.resize(w, h, pad);
    AtrousImage a, b;
    a.resize(w, h, pad);
    b.resize(w, h, pad);
    PaddedPlane zi, zs, cs;
    for (PaddedPlane* p : {&zi, &zs, &cs}) p->resize(w, h, pad);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        g.depth.at(x, y) = 2.0f;
        g.normal[2].at(x, y) = 1.0f;
        const float v = x < 16 ? 0.2f : 0.8f;
        for (int c = 0; c < 3; ++c) a.color[c].at(x, y) = v;
        a.lum.at(x, y) = v;
        a.var.at(x, y) = 1.0f;  // noisy: w_l alone would blur across
        zi.at(x, y) = x < 16 ? 1.0f : 3.0f;
        zs.at(x, y) = 1.0f - roughness;
        cs.at(x, y) = 1.0f / roughnessWeight(roughness);
      }
    AtrousLevel lv;
    lv.step = 1;
    if (glossy) {
      lv.indirectDistance = &zi;
      lv.indirectDistanceScale = &zs;
      lv.centreScale = &cs;
    }
    atrousLevel(g, lv, a, b);
    return b.color[0].at(16, 4) - b.color[0].at(15, 4);
  };
  EXPECT_NEAR(contrast(0.0f, true), 0.6f, 0.01f);          // the edge survives
  EXPECT_LT(contrast(0.0f, false), 0.5f);                  // without the weights it blurs
  EXPECT_NEAR(contrast(1.0f, true), contrast(1.0f, false), 0.02f);  // rough: as without
}

// ---------------------------------------------------------------- variance (checklist 22)

TEST(GersthoferVariance, SpatialEstimateIsGuidedByMeshId) {
  // Two meshes side by side, flat and equally deep, each of constant luminance: with the
  // mesh-id term the 3x3 estimate sees one value per pixel (variance 0); without it the border
  // pixels mix both.
  const int w = 16, h = 8, pad = 8;
  AtrousGuide g;
  g.resize(w, h, pad);
  PaddedPlane a, b, var, ids;
  for (PaddedPlane* p : {&a, &b, &var, &ids}) p->resize(w, h, pad);
  Plane length(w, h, 1.0f);  // short history everywhere
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      g.depth.at(x, y) = 2.0f;
      g.normal[2].at(x, y) = 1.0f;
      const float l = x < 8 ? 10.0f : 60.0f;
      a.at(x, y) = l;
      b.at(x, y) = l * l;
      ids.at(x, y) = x < 8 ? 1.0f : 2.0f;
    }
  spatialVariance(g, a, b, length, 4.0f, 1, 1.0f, 1e-2f, 0.0f, 128, var, &ids);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) EXPECT_NEAR(var.at(x, y), 0.0f, 1e-2f) << x;
  spatialVariance(g, a, b, length, 4.0f, 1, 1.0f, 1e-2f, 0.0f, 128, var, nullptr);
  EXPECT_GT(var.at(7, 4), 100.0f);  // 3 of 9 taps across the border: (50^2) * 2/9 * ... > 0
  EXPECT_NEAR(var.at(3, 4), 0.0f, 1e-2f);
}

// ---------------------------------------------------------------- temporal (checklist 17)

TEST(GersthoferTemporal, FixedAlphaAfterTheFirstFrameAndNineSampleVariance) {
  const int w = 64, h = 64;
  FrameData f = test::toFrameData(test::flatFrame(w, h, 1.0f));
  Reprojection rp;
  TemporalAccumulator acc;
  acc.resize(w, h);
  AccumulationOptions opt;
  opt.cumulativeColor = false;
  opt.cumulativeMoments = false;
  std::mt19937 rng(2);
  std::normal_distribution<float> noise(1.0f, 0.5f);
  Plane3 c;
  rtd::resize(c, w, h);
  const FrameData* previous = nullptr;
  FrameData prev = f;
  for (int k = 0; k < 60; ++k) {
    reproject(f, previous, ReprojectionSettings{}, rp);
    for (auto& p : c)
      for (auto& v : p.data) v = k == 0 ? 3.0f : k == 1 ? 8.0f : noise(rng);
    acc.run(rp, c, 0.2f, 0.2f, 255, opt);
    previous = &prev;
    if (k == 0) {
      EXPECT_FLOAT_EQ(acc.color()[0](5, 5), 3.0f);  // no history: the sample
    }
    if (k == 1) {
      EXPECT_FLOAT_EQ(acc.color()[0](5, 5), 0.2f * 8.0f + 0.8f * 3.0f);  // fixed 0.2, not 1/2
      EXPECT_EQ(acc.historyLength()(5, 5), 2.0f);
    }
    for (size_t i = 0; i < acc.moment1().data.size(); ++i)
      ASSERT_GE(acc.moment2().data[i], acc.moment1().data[i] * acc.moment1().data[i] - 1e-4f);
  }
  EXPECT_EQ(acc.historyLength()(7, 9), 60.0f);
  // EMA of i.i.d. noise: Var = sigma^2 alpha / (2 - alpha) = sigma^2 / 9 (about a 9-sample mean).
  double s = 0, s2 = 0;
  for (float v : acc.color()[0].data) s += v, s2 += double(v) * v;
  const double n = double(w) * h, var = s2 / n - (s / n) * (s / n);
  EXPECT_NEAR(var / (0.25 / 9.0), 1.0, 0.12);
}

// ---------------------------------------------------------------- masking (checklist 12-14)

TEST(GersthoferMask, CoverageCountsVisiblePixelsOnly) {
  Plane mask(8, 4, 0.0f), hidden(8, 4, 0.0f);
  for (int x = 0; x < 8; ++x) mask(x, 0) = 1.0f;  // 8 of 32
  EXPECT_FLOAT_EQ(sampleCoverage(mask, nullptr), 0.25f);
  for (int x = 0; x < 8; ++x) hidden(x, 3) = 1.0f;  // 8 of 24 visible
  EXPECT_FLOAT_EQ(sampleCoverage(mask, &hidden), 1.0f / 3.0f);
}

// One frame at coverage 1/4 (a quarter of the pixels sampled, the rest black), right after a
// camera cut; mean of the denoised output. Gersthofer Fig. 5.8 and Eq. 3.1.
double maskedMean(bool boost, double* unmasked = nullptr) {
  auto d = Device::create()->createDenoiser(gersthofer());
  d->set("maskBoost", boost ? "true" : "false");
  const auto scene = tinyScene(0.0f);
  Frame f = splitFrame(scene, 0);
  Image out(scene.width, scene.height, 3);
  if (unmasked) {
    d->denoise(f.inputs(), out.view());
    *unmasked = mean(out);
    d->reset();
  }
  Image mask(scene.width, scene.height, 1);
  for (int y = 0; y < scene.height; ++y)
    for (int x = 0; x < scene.width; ++x) {
      const bool traced = (x + 2 * y) % 4 == 0;
      mask.at(x, y) = traced ? 1.0f : 0.0f;
      if (!traced)
        for (Buffer b : {Buffer::Color, Buffer::IndirectDiffuse})
          for (int c = 0; c < 3; ++c) f[b].at(x, y, c) = 0.0f;
    }
  f[Buffer::SampleMask] = mask;
  FrameInputs in = f.inputs();
  in.cameraCut = true;
  d->denoise(in, out.view());
  EXPECT_FALSE(hasPass(d->stats(), "median"));  // off while masking (checklist 14)
  return mean(out);
}

TEST(GersthoferMask, BoostKeepsTheBrightnessOfDisoccludedPixels) {
  double unmasked = 0;
  const double boosted = maskedMean(true, &unmasked), plain = maskedMean(false);
  std::printf("coverage 1/4 after a cut: mean %.4f with the 1/c boost, %.4f without, %.4f unmasked\n", boosted, plain,
              unmasked);
  // Measured (48x32, the gersthofer preset): 0.82 and 0.20 of the unmasked mean. The boost is
  // a factor 1/c = 4 on the disoccluded samples; the edge-stopping filter, weighing black
  // neighbours less than bright ones, keeps a little of the darkening (the thesis' "dark
  // trails ... only partly fixed").
  EXPECT_NEAR(boosted / plain, 4.0, 0.4);
  EXPECT_NEAR(boosted / unmasked, 1.0, 0.25);
  EXPECT_NEAR(plain / unmasked, 0.25, 0.07);
}

TEST(GersthoferMask, AnAllOnesMaskIsNoMasking) {
  // The renderer writes sampleMask on every frame; a fully traced one must not turn the median
  // off or change anything.
  const auto scene = tinyScene();
  SvgfSettings s = gersthofer();
  s.fxaa = false;  // its edge decisions would magnify the rounding difference below
  auto a = Device::create()->createDenoiser(s), b = Device::create()->createDenoiser(s);
  Image oa(scene.width, scene.height, 3), ob = oa;
  for (int k = 0; k < 2; ++k) {
    Frame f = splitFrame(scene, k);
    a->denoise(f.inputs(), oa.view());
    f[Buffer::SampleMask] = Image(scene.width, scene.height, 1, 1.0f);
    b->denoise(f.inputs(), ob.view());
    // Equal up to rounding: with a mask the accumulation takes its scalar path, without one
    // the vector path (fused multiply-adds).
    EXPECT_LT(maxAbsDiff(oa, ob), 1e-5);
    EXPECT_TRUE(hasPass(b->stats(), "median"));
  }
}

TEST(GersthoferMask, BoostOnlyWhereReprojectionFailed) {
  const int w = 8, h = 4;
  Reprojection rp;
  rp.resize(w, h);  // every pixel None
  Plane len(w, h, 0.0f), mask(w, h, 1.0f), factor(w, h);
  mask(1, 0) = 0.0f;
  EXPECT_EQ(boostDisoccluded(rp, len, mask, 0.25f, factor), size_t(w * h - 1));
  EXPECT_EQ(factor(0, 0), 4.0f);
  EXPECT_EQ(factor(1, 0), 1.0f);  // not sampled
  // A pixel with a valid tap that holds history is not boosted; one whose taps hold none is.
  rp.kind[2] = rp.kind[3] = Reprojection::Bilinear;
  rp.base[2] = 2;
  rp.base[3] = 4;
  rp.weights[2] = rp.weights[3] = {1, 0, 0, 0};
  len(2, 0) = 5.0f;
  boostDisoccluded(rp, len, mask, 0.25f, factor);
  EXPECT_EQ(factor(2, 0), 1.0f);
  EXPECT_EQ(factor(3, 0), 4.0f);
}

TEST(GersthoferMask, TheBoostStaysOutOfTheHistory) {
  // A still view traced at c = 1/4 in a rotating pattern: after one cycle every pixel has
  // history; were the boosted first samples accumulated, the image would stay up to 4x too
  // bright for many frames. Unfiltered, the output is then the plain accumulation: the colour.
  const auto scene = tinyScene(0.0f);
  SvgfSettings s = gersthofer();
  s.atrousIterations = 0;
  s.fxaa = false;
  auto d = Device::create()->createDenoiser(s);
  Image out(scene.width, scene.height, 3);
  const Frame clean = [&] {
    auto t = scene;
    t.noise = 0.0f;
    return splitFrame(t, 0);
  }();
  for (int k = 0; k < 8; ++k) {
    Frame f = clean;
    f[Buffer::SampleMask] = Image(scene.width, scene.height, 1);
    for (int y = 0; y < scene.height; ++y)
      for (int x = 0; x < scene.width; ++x) {
        const bool traced = (x + 2 * y + k) % 4 == 0;
        f[Buffer::SampleMask].at(x, y) = traced ? 1.0f : 0.0f;
        if (!traced)
          for (Buffer b : {Buffer::Color, Buffer::IndirectDiffuse})
            for (int c = 0; c < 3; ++c) f[b].at(x, y, c) = 0.0f;
      }
    d->denoise(f.inputs(), out.view());
    if (k >= 4) { EXPECT_LT(maxAbsDiff(out, clean[Buffer::Color]), 1e-4) << "frame " << k; }
  }
}

// ---------------------------------------------------------------- composite, median (checklist 19, 21)

TEST(GersthoferComposite, EqualsTheSumOfItsPartsForNoiseFreeInput) {
  // Noise-free, smooth components: A a ramp in x, B a ramp in y; Color = A + B.
  const int w = 40, h = 24;
  Frame f = test::flatFrame(w, h, 0.0f);
  f[Buffer::IndirectDiffuse] = Image(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const float a = 0.1f + 0.02f * x * (c + 1), b = 0.3f + 0.01f * y;
        f[Buffer::Color].at(x, y, c) = a + b;
        f[Buffer::IndirectDiffuse].at(x, y, c) = b;
      }
  SvgfSettings s = gersthofer();
  s.atrousIterations = 0;  // the composite itself, unfiltered
  s.fxaa = false;
  auto d = Device::create()->createDenoiser(s);
  Image out(w, h, 3);
  for (int k = 0; k < 3; ++k) {
    d->denoise(f.inputs(), out.view());
    EXPECT_TRUE(hasPass(d->stats(), "median"));  // the median of a ramp is the ramp
    EXPECT_LT(maxAbsDiff(out, f[Buffer::Color]), 2e-5) << "frame " << k;
  }
  // Filtered (five levels, glossy weights, FXAA): a noise-free constant stays itself.
  Frame g = test::flatFrame(w, h, 0.75f);
  g[Buffer::IndirectDiffuse] = Image(w, h, 3, 0.25f);
  g[Buffer::Roughness] = Image(w, h, 1, 0.3f);
  g[Buffer::SecondaryDistance] = Image(w, h, 1, 1.5f);
  auto full = Device::create()->createDenoiser(gersthofer());
  for (int k = 0; k < 3; ++k) full->denoise(g.inputs(), out.view());
  EXPECT_LT(maxAbsDiff(out, g[Buffer::Color]), 2e-5);
}

TEST(GersthoferComposite, MedianIsTheExactMedianOfNine) {
  // Against sorting the nine clamped neighbours (std::nth_element), ties included.
  const int w = 37, h = 11;
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> u(0, 6);
  Plane3 in, out;
  rtd::resize(in, w, h);
  rtd::resize(out, w, h);
  for (auto& p : in)
    for (auto& v : p.data) v = 0.5f * float(u(rng));
  svgf::median3x3(in, nullptr, out);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float v[9];
        int k = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) v[k++] = in[c](std::clamp(x + dx, 0, w - 1), std::clamp(y + dy, 0, h - 1));
        std::nth_element(v, v + 4, v + 9);
        ASSERT_EQ(out[c](x, y), v[4]) << x << "," << y;
      }
}

TEST(GersthoferComposite, MedianRemovesAnIndirectDiffuseFirefly) {
  const int w = 16, h = 16;
  Frame f = test::flatFrame(w, h, 0.5f);
  f[Buffer::IndirectDiffuse] = Image(w, h, 3, 0.2f);
  for (int c = 0; c < 3; ++c) {
    f[Buffer::Color].at(8, 8, c) += 50.0f;  // a caustic path through the diffuse lobe
    f[Buffer::IndirectDiffuse].at(8, 8, c) += 50.0f;
  }
  SvgfSettings s = gersthofer();
  s.atrousIterations = 0;
  s.fxaa = false;
  auto d = Device::create()->createDenoiser(s);
  Image out(w, h, 3);
  d->denoise(f.inputs(), out.view());
  EXPECT_NEAR(out.at(8, 8, 1), 0.5f, 1e-5f);  // (0.5 - 0.2) + median 0.2
  s.indirectDiffuseMedian = false;
  d->setSettings(s);
  d->reset();
  d->denoise(f.inputs(), out.view());
  EXPECT_NEAR(out.at(8, 8, 1), 50.5f, 1e-4f);
}

// ---------------------------------------------------------------- history (checklist 18)

TEST(GersthoferHistory, HistoryIsTheTemporalOutput) {
  // With feedbackLevel 0 and a still camera, the output of an unfiltered pipeline (no levels)
  // equals a plain fixed-alpha accumulation of the composite: nothing filtered went back.
  const auto scene = tinyScene(0.0f);
  SvgfSettings s = gersthofer();
  auto filtered = Device::create()->createDenoiser(s);
  s.atrousIterations = 0;
  s.fxaa = false;
  s.indirectDiffuseMedian = false;
  auto plain = Device::create()->createDenoiser(s);
  Image a(scene.width, scene.height, 3), b(scene.width, scene.height, 3), expected(scene.width, scene.height, 3);
  for (int k = 0; k < 4; ++k) {
    const Frame f = splitFrame(scene, k);
    filtered->denoise(f.inputs(), a.view());  // its filter must not touch its history
    plain->denoise(f.inputs(), b.view());
    for (size_t i = 0; i < expected.pixels.size(); ++i) {
      const float alb = f[Buffer::Albedo].pixels[i] > 1e-3f ? f[Buffer::Albedo].pixels[i] : 1.0f;
      const float sample = f[Buffer::Color].pixels[i] / alb;
      expected.pixels[i] = (k == 0 ? sample : 0.2f * sample + 0.8f * expected.pixels[i] / alb) * alb;
    }
    EXPECT_LT(maxAbsDiff(b, expected), 1e-4) << k;
  }
  // And a filtered run's fifth output differs from a run whose history is fed back.
  SvgfSettings fb = gersthofer();
  fb.feedbackLevel = 1;
  auto fed = Device::create()->createDenoiser(fb);
  Image c(scene.width, scene.height, 3);
  for (int k = 0; k < 4; ++k) fed->denoise(splitFrame(scene, k).inputs(), c.view());
  EXPECT_GT(maxAbsDiff(a, c), 1e-3);
}

// ---------------------------------------------------------------- post-processing (checklist 25)

TEST(GersthoferPost, AcesMatchesTheNarkowiczFit) {
  EXPECT_FLOAT_EQ(tonemap::acesNarkowicz(0.0f), 0.0f);
  EXPECT_NEAR(tonemap::acesNarkowicz(1.0f), 2.54 / 3.16, 1e-6);
  EXPECT_NEAR(tonemap::acesNarkowicz(0.18f), 0.086724 / 0.324932, 1e-6);
  EXPECT_FLOAT_EQ(tonemap::acesNarkowicz(10.0f), 1.0f);  // 251.3 / 249.04 clamped
}

TEST(GersthoferPost, FxaaSmoothsStaircasesKeepsFlatRegionsAndStraightEdges) {
  const int w = 48, h = 32;
  Plane3 in, out;
  Plane luma(w, h);
  rtd::resize(in, w, h);
  rtd::resize(out, w, h);
  auto run = [&](auto image) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) in[c](x, y) = image(x, y);
    fxaa(in, FxaaParams{}, luma, out);
  };
  run([](int, int) { return 0.6f; });
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ASSERT_EQ(out[1](x, y), 0.6f);
  run([](int x, int) { return x < 20 ? 0.0f : 1.0f; });  // a straight vertical edge
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) EXPECT_NEAR(out[1](x, y), in[1](x, y), 0.1f) << x << "," << y;
  // A shallow aliased line (1 px step every 6 columns): the steps become gradients.
  run([](int x, int y) { return y >= 10 + x / 6 ? 1.0f : 0.0f; });
  int blended = 0;
  double before = 0, after = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      blended += out[1](x, y) > 0.05f && out[1](x, y) < 0.95f;
      before += in[1](x, y);
      after += out[1](x, y);
    }
  EXPECT_GT(blended, w);  // along the whole edge
  EXPECT_NEAR(after / before, 1.0, 0.02);
}

TEST(GersthoferPost, ToneMapIsTheLastStepAfterFxaa) {
  const auto scene = tinyScene();
  SvgfSettings s = gersthofer();
  auto linear = Device::create()->createDenoiser(s);
  s.toneMap = SvgfToneMap::aces;
  auto mapped = Device::create()->createDenoiser(s);
  Image a(scene.width, scene.height, 3), b(scene.width, scene.height, 3);
  for (int k = 0; k < 2; ++k) {
    const Frame f = splitFrame(scene, k);
    linear->denoise(f.inputs(), a.view());
    mapped->denoise(f.inputs(), b.view());
  }
  for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_NEAR(b.pixels[i], tonemap::acesNarkowicz(a.pixels[i]), 1e-6) << i;
}

// ---------------------------------------------------------------- two views (checklist 1, 20, 27)

TEST(GersthoferStereo, WithoutEyeReprojectionEachEyeIsASingleViewDenoiser) {
  auto device = Device::create();
  SvgfSettings s = gersthofer();
  s.eyeReprojection = false;
  auto stereo = device->createStereoDenoiser(s);
  auto left = device->createDenoiser(s), right = device->createDenoiser(s);
  auto scene = tinyScene();
  auto other = scene;
  other.seed = 9;  // the right eye: other noise
  Image ol(scene.width, scene.height, 3), orr(scene.width, scene.height, 3), sl = ol, sr = ol;
  for (int k = 0; k < 3; ++k) {
    const Frame fl = splitFrame(scene, k), fr = splitFrame(other, k);
    StereoFrameInputs in;
    in.eye[0] = fl.inputs();
    in.eye[1] = fr.inputs();
    stereo->denoise(in, ol.view(), orr.view());
    left->denoise(fl.inputs(), sl.view());
    right->denoise(fr.inputs(), sr.view());
    EXPECT_EQ(ol.pixels, sl.pixels);
    EXPECT_EQ(orr.pixels, sr.pixels);
    EXPECT_GT(maxAbsDiff(ol, orr), 1e-3);  // separate histories
  }
  EXPECT_FALSE(hasPass(stereo->stats(), "eyeReprojection"));
}

TEST(GersthoferStereo, IdenticalEyesExchangeTheirOwnLight) {
  auto device = Device::create();
  // FXAA off: its edge decisions are discontinuous, so the projection's rounding (1e-5 px)
  // could flip one; everything before it is continuous in its input.
  SvgfSettings s = gersthofer();
  s.fxaa = false;
  auto stereo = device->createStereoDenoiser(s);
  auto single = device->createDenoiser(s);
  const auto scene = tinyScene();
  Image l(scene.width, scene.height, 3), r = l, o = l;
  for (int k = 0; k < 3; ++k) {
    const Frame f = splitFrame(scene, k);
    StereoFrameInputs in;
    in.eye[0] = f.inputs();
    in.eye[1] = f.inputs();
    stereo->denoise(in, l.view(), r.view());
    single->denoise(f.inputs(), o.view());
    // Zero separation, the same light in both eyes: the exchanged light is the eye's own.
    EXPECT_LT(maxAbsDiff(l, o), 2e-4) << k;
    EXPECT_LT(maxAbsDiff(r, o), 2e-4) << k;
  }
  EXPECT_TRUE(hasPass(stereo->stats(), "eyeReprojection"));
  EXPECT_TRUE(hasPass(stereo->eyeStats(0), "atrous5"));
}

TEST(GersthoferStereo, SharedIndirectDiffuseIsLessNoisy) {
  // The same view in both eyes with independent noise (zero separation): sharing the
  // indirect diffuse (here all of the light) brings both eyes closer to the reference.
  auto device = Device::create();
  SvgfSettings s = gersthofer();
  s.atrousIterations = 0;  // the temporal part and the exchange alone
  s.fxaa = false;
  s.indirectDiffuseMedian = false;  // the median of exponential noise is biased: MSE would not halve
  auto shared = device->createStereoDenoiser(s);
  s.eyeReprojection = false;
  auto apart = device->createStereoDenoiser(s);
  auto scene = tinyScene(0.0f);
  scene.width = 128;
  scene.height = 96;
  auto other = scene;
  other.seed = 17;
  Image ref, a0(scene.width, scene.height, 3), a1 = a0, b0 = a0, b1 = a0;
  for (int k = 0; k < 3; ++k) {
    const Frame fl = splitFrame(scene, k, 1.0f, &ref), fr = splitFrame(other, k, 1.0f);
    StereoFrameInputs in;
    in.eye[0] = fl.inputs();
    in.eye[1] = fr.inputs();
    shared->denoise(in, a0.view(), a1.view());
    apart->denoise(in, b0.view(), b1.view());
  }
  auto mse = [&](const Image& x) {
    double e = 0;
    for (size_t i = 0; i < x.pixels.size(); ++i) e += std::pow(double(x.pixels[i]) - ref.pixels[i], 2);
    return e / x.pixels.size();
  };
  // Two independent estimates averaged: about half the error variance (both eyes together:
  // the exponential noise makes one eye's error a noisy estimate).
  std::printf("MSE shared / apart: left %.3f, right %.3f\n", mse(a0) / mse(b0), mse(a1) / mse(b1));
  EXPECT_NEAR((mse(a0) + mse(a1)) / (mse(b0) + mse(b1)), 0.5, 0.08);
}

TEST(GersthoferStereo, ReportsMemoryAndValidatesBothEyes) {
  auto device = Device::create();
  SvgfSettings s = gersthofer();
  auto stereo = device->createStereoDenoiser(s);
  const auto scene = tinyScene();
  const Frame f = splitFrame(scene, 0);
  StereoFrameInputs in;
  in.eye[0] = f.inputs();
  in.eye[1] = f.inputs();
  Image l(scene.width, scene.height, 3), r = l, small(8, 8, 3);
  stereo->denoise(in, l.view(), r.view());
  const uint64_t px = uint64_t(scene.width) * scene.height;
  uint64_t history = 0, intermediate = 0, frames = 0;
  for (const auto& m : stereo->stats().memory) {
    if (m.category == "history") history = m.bytes;
    if (m.category == "intermediate") intermediate = m.bytes;
    if (m.category == "frames") frames = m.bytes;
  }
  // Per eye: composite and indirect diffuse accumulators (2 x 6 planes each, double-buffered)
  // and the indirect ray length (2 planes): 26 float planes; TAA is off in the preset.
  EXPECT_EQ(history, 2 * 26 * 4 * px);
  EXPECT_GT(intermediate, 2 * 30 * 4 * px);
  EXPECT_GT(frames, 2 * 10 * 4 * px);
  // One eye of the wrong size: an error before either eye runs.
  StereoFrameInputs bad = in;
  const Frame g = splitFrame([] { auto t = tinyScene(); t.width = 8; t.height = 8; return t; }(), 0);
  bad.eye[1] = g.inputs();
  EXPECT_THROW(stereo->denoise(bad, l.view(), small.view()), Error);
  EXPECT_THROW(stereo->denoise(in, l.view(), small.view()), Error);
}

TEST(GersthoferStereo, OtherMethodsRunPerEye) {
  auto device = Device::create();
  auto stereo = device->createStereoDenoiser("accumulate");
  auto single = device->createDenoiser("accumulate");
  const auto scene = tinyScene();
  Image l(scene.width, scene.height, 3), r = l, s = l;
  for (int k = 0; k < 2; ++k) {
    const Frame f = splitFrame(scene, k);
    StereoFrameInputs in;
    in.eye[0] = f.inputs();
    in.eye[1] = f.inputs();
    stereo->denoise(in, l.view(), r.view());
    single->denoise(f.inputs(), s.view());
  }
  EXPECT_EQ(l.pixels, s.pixels);
  EXPECT_EQ(r.pixels, s.pixels);
  EXPECT_EQ(stereo->method(), "accumulate");
}

}  // namespace
}  // namespace rtd
