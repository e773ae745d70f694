// SVGF's Voorhuis mode (docs/methods/reflections.md): per-class blend factors, the roughness
// switch, glossy reprojection without consistency tests, neighbourhood clipping, Eq. 6 and
// the demodulation and edge stopping of pure speculars; which parts run on which input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string_view>
#include <vector>

#include "core/frame_data.h"
#include "methods/svgf/svgf_reflections.h"
#include "passes/neighbourhood_clipping.h"
#include "passes/taa.h"
#include "passes/temporal_accumulation.h"
#include "rtd/rtd.h"
#include "support/cpu_paths.h"
#include "support/planes_kept.h"
#include "support/runs_as_fresh.h"

namespace rtd {
namespace {

// A frame of planes: a plane facing the camera at depth 2 (normal +z), camera at the origin.
struct TestFrame {
  int w, h;
  FrameData f;
  TestFrame(int width, int height) : w(width), h(height) {
    f.width = w;
    f.height = h;
    for (Buffer b : {Buffer::Color, Buffer::Albedo, Buffer::Normal, Buffer::Depth, Buffer::Position})
      set(b, 0.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        f.plane(Buffer::Normal, 2)(x, y) = 1.0f;
        f.plane(Buffer::Depth)(x, y) = 2.0f;
        f.plane(Buffer::Position, 0)(x, y) = 0.01f * x;
        f.plane(Buffer::Position, 1)(x, y) = -0.01f * y;
        f.plane(Buffer::Position, 2)(x, y) = -2.0f;
        for (int c = 0; c < 3; ++c) f.plane(Buffer::Albedo, c)(x, y) = 1.0f;
      }
  }
  void set(Buffer b, float v) { f.buffers[int(b)].assign(bufferChannelCount(b), Plane(w, h, v)); }
  Plane& p(Buffer b, int c = 0) { return f.plane(b, c); }
};

SvgfSettings ours() { return SvgfSettings::forVariant(SvgfVariant::voorhuis); }

// Static view, no motion: every pixel reprojects onto itself.
Reprojection identity(const FrameData& cur, const FrameData& prev) {
  Reprojection rp;
  reproject(cur, &prev, ReprojectionSettings{}, rp);
  return rp;
}
// No previous frame: every pixel starts a history.
Reprojection noHistory(const FrameData& f) {
  Reprojection rp;
  reproject(f, nullptr, ReprojectionSettings{}, rp);
  return rp;
}

// ---------------------------------------------------------------- item 2: per-class alpha

TEST(VoorhuisAlpha, DiffuseBlendsPointTwoAndSpecularPointOne) {
  // Left half diffuse (roughness 1), right half specular (0.3). History y = 1 for 40 frames,
  // then x = 5: one frame later diffuse pixels hold 0.2 x + 0.8 y, specular 0.1 x + 0.9 y.
  TestFrame t(16, 8);
  t.set(Buffer::Roughness, 1.0f);
  for (int y = 0; y < 8; ++y)
    for (int x = 8; x < 16; ++x) t.p(Buffer::Roughness)(x, y) = 0.3f;
  const SvgfSettings s = ours();
  const svgf::ReflectionParts parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return t.f.has(b); }, false);
  ASSERT_TRUE(parts.materialAlpha);
  svgf::Reflections refl;
  refl.resize(16, 8, 8);
  const Reprojection rp = identity(t.f, t.f);
  refl.prepare(t.f, &t.f, s, parts, false, rp);
  const svgf::StreamPlan plan{Buffer::Color, "color", true, false};
  AtrousGuide guide;
  const auto in = refl.stream(t.f, plan, rp, guide, 0);
  ASSERT_NE(in.alpha, nullptr);
  TemporalAccumulator acc;
  acc.resize(16, 8);
  Plane3 c;
  resize(c, 16, 8, 1.0f);
  AccumulationOptions opt;
  opt.alphaPlane = in.alpha;
  for (int k = 0; k < 40; ++k) acc.run(k == 0 ? noHistory(t.f) : rp, c, s.alphaColor, s.alphaMoments, 255, opt);
  resize(c, 16, 8, 5.0f);
  acc.run(rp, c, s.alphaColor, s.alphaMoments, 255, opt);
  EXPECT_NEAR(acc.color()[0](2, 3), 0.2f * 5 + 0.8f * 1, 1e-5);
  EXPECT_NEAR(acc.color()[1](12, 3), 0.1f * 5 + 0.9f * 1, 1e-5);
}

// ---------------------------------------------------------------- item 13: roughness switch

TEST(VoorhuisClasses, RoughnessSweepSwitchesMotionSourceExactlyAtTheThreshold) {
  const int w = 101, h = 2;
  TestFrame t(w, h);
  t.set(Buffer::Roughness, 0.0f);
  t.set(Buffer::Metalness, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) t.p(Buffer::Roughness)(x, y) = float(x) / 100.0f;  // 0.00 .. 1.00
  PixelVector<uint8_t> cls;
  classifySurfaces(t.f, {}, false, cls);
  for (int x = 0; x < w; ++x) {
    const float r = t.p(Buffer::Roughness)(x, 0);
    const SurfaceClass c = SurfaceClass(cls[x]);
    if (r < 0.02f) { EXPECT_EQ(c, SurfaceClass::Mirror) << r; }
    else if (r < 0.4f) { EXPECT_EQ(c, SurfaceClass::GlossyReflection) << r; }
    else if (r < 0.9f) { EXPECT_EQ(c, SurfaceClass::Glossy) << r; }
    else EXPECT_EQ(c, SurfaceClass::Diffuse) << r;
  }
  EXPECT_EQ(SurfaceClass(cls[39]), SurfaceClass::GlossyReflection);
  EXPECT_EQ(SurfaceClass(cls[40]), SurfaceClass::Glossy);  // 0.4: primary motion
  // The searched pixels (the MV source "reflection") are exactly those below 0.4.
  t.set(Buffer::MirrorDirection, 0.0f);
  t.set(Buffer::SecondaryDistance, 1.0f);
  t.set(Buffer::ReflectedPosition, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      t.p(Buffer::MirrorDirection, 2)(x, y) = 1.0f;
      t.p(Buffer::ReflectedPosition, 0)(x, y) = float(x);
    }
  Reprojection out;
  ReflectionMotionStats st;
  specularReprojection(t.f, &t.f, cls, cls, identity(t.f, t.f), SpecularMotion::Reflection, {}, out, &st);
  EXPECT_EQ(st.mirrorPixels, uint64_t(2 * 2));     // 0.00, 0.01
  EXPECT_EQ(st.glossyPixels, uint64_t(2 * 38));    // 0.02 .. 0.39
  EXPECT_EQ(st.matched, st.mirrorPixels + st.glossyPixels);
}

// ---------------------------------------------------------------- item 14: no consistency tests for glossy

TEST(VoorhuisReprojection, GlossyAccumulatesAcrossANormalChangeWhereDiffuseResets) {
  // The previous frame's normals are turned by 60 degrees (a deforming surface, or a glossy
  // reflection whose features change): the primary reprojection rejects every tap. Glossy
  // pixels (roughness 0.2) follow their representative rays, unchanged, and keep history.
  const int w = 12, h = 6;
  TestFrame prev(w, h), cur(w, h);
  for (TestFrame* t : {&prev, &cur}) {
    t->set(Buffer::Roughness, 1.0f);
    t->set(Buffer::MirrorDirection, 0.0f);
    t->set(Buffer::SecondaryDistance, 3.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (x >= 6) t->p(Buffer::Roughness)(x, y) = 0.2f;
        t->p(Buffer::MirrorDirection, 2)(x, y) = 1.0f;
      }
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      prev.p(Buffer::Normal, 2)(x, y) = 0.5f;
      prev.p(Buffer::Normal, 0)(x, y) = std::sqrt(0.75f);
    }
  PixelVector<uint8_t> cls, prevCls;
  classifySurfaces(cur.f, {}, false, cls);
  classifySurfaces(prev.f, {}, false, prevCls);
  Reprojection primary;
  reproject(cur.f, &prev.f, ReprojectionSettings{}, primary);
  Reprojection rp;
  specularReprojection(cur.f, &prev.f, cls, prevCls, primary, SpecularMotion::Reflection, {}, rp);
  TemporalAccumulator acc;
  acc.resize(w, h);
  Plane3 c;
  resize(c, w, h, 1.0f);
  acc.run(noHistory(prev.f), c, 0.2f, 0.2f, 255);  // the previous frame: n = 1 everywhere
  acc.run(rp, c, 0.2f, 0.2f, 255);
  for (int y = 0; y < h; ++y) {
    EXPECT_EQ(acc.historyLength()(2, y), 1.0f) << "diffuse pixel keeps a rejected history";
    EXPECT_EQ(acc.historyLength()(9, y), 2.0f) << "glossy pixel lost its history";
  }
}

TEST(VoorhuisTaa, FollowsTheReflectionMotionOnMirrorsAndNoHistoryForNoSpecReproj) {
  // A roughness sweep (mirrors 0.00-0.01, glossy 0.02-0.39, then glossy 0.4-0.89 and diffuse)
  // whose reflections moved 3 px: the previous frame's pixel x + 3 has the reflection features
  // (reflected position, representative ray) of the current pixel x; the primary motion is 0.
  // TAA takes the reflection motion on mirror pixels, the primary one elsewhere unless
  // taaGlossyReflectionMotion; NoSpecReproj gives TAA no history on any specular pixel;
  // taaMirrorHistory gives the mirror pixels the primary motion or no history instead.
  const int w = 101, h = 2, shift = 3;
  TestFrame prev(w, h), cur(w, h);
  for (TestFrame* t : {&prev, &cur})
    for (Buffer b : {Buffer::Roughness, Buffer::Metalness, Buffer::MirrorDirection, Buffer::SecondaryDistance,
                     Buffer::ReflectedPosition, Buffer::ReflectedNormal, Buffer::ReflectedAlbedo})
      t->set(b, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto features = [&](TestFrame& t, int px, int from) {
        t.p(Buffer::Roughness)(px, y) = float(from) / 100.0f;
        t.p(Buffer::ReflectedPosition, 0)(px, y) = 0.1f * from;
        t.p(Buffer::Position, 0)(px, y) = 0.01f * from;  // representative rays: parallel lines
        for (int c = 0; c < 2; ++c) t.p(Buffer::MirrorDirection, c)(px, y) = 0.0f;
        for (int c = 0; c < 2; ++c) t.p(Buffer::ReflectedNormal, c)(px, y) = 0.0f;
      };
      features(cur, x, x);
      features(prev, x, x - shift);
    }
  for (const char* variant : {"voorhuis", "voorhuisNoSpecReproj"})
    for (SvgfTaaMirrorHistory mirrors : {SvgfTaaMirrorHistory::reflectionMotion, SvgfTaaMirrorHistory::primaryMotion,
                                         SvgfTaaMirrorHistory::none})
    for (bool glossy : {false, true}) {
      SvgfSettings s = SvgfSettings::forVariant(variant == std::string("voorhuis") ? SvgfVariant::voorhuis
                                                                                  : SvgfVariant::voorhuisNoSpecReproj);
      s.preferLobes = false;
      const auto parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return cur.f.has(b); }, false);
      svgf::Reflections r;
      r.resize(w, h, 0);
      const Reprojection first = noHistory(prev.f), primary = identity(cur.f, prev.f);
      r.prepare(prev.f, nullptr, s, parts, false, first);
      r.prepare(cur.f, &prev.f, s, parts, false, primary);
      const Reprojection& taa = r.taaMotion(cur.f, primary, glossy, mirrors);
      // The whole record, not only the position (TAA's Catmull-Rom fetch reads it): where TAA
      // follows the primary motion, the primary record; a constant frame through the
      // Catmull-Rom TAA on this record stays constant.
      ASSERT_EQ(taa.kind.size(), size_t(w) * h);
      for (int x = 0; x < w; ++x)
        if (taa.prevX(x, 0) == primary.prevX(x, 0) && taa.prevY(x, 0) == primary.prevY(x, 0)) {
          EXPECT_EQ(taa.kind[size_t(x)], primary.kind[size_t(x)]) << x;
          EXPECT_EQ(taa.base[size_t(x)], primary.base[size_t(x)]) << x;
          EXPECT_EQ(taa.weights[size_t(x)], primary.weights[size_t(x)]) << x;
        }
      {
        TaaSettings ts;
        ts.taaHistoryFilter = TaaHistoryFilter::catmullRom;
        Plane3 grey;
        resize(grey, w, h, 0.5f);
        Taa t;
        t.run(taa, grey, ts);
        const Plane3& out = t.run(taa, grey, ts);
        for (int c = 0; c < 3; ++c)
          for (float v : out[c].data) ASSERT_NEAR(v, 0.5f, 1e-6f) << variant;
      }
      for (int x = shift; x < w - shift; ++x) {
        const float rough = float(x) / 100.0f, px = taa.prevX(x, 0);
        if (variant != std::string("voorhuis")) {  // whatever taaMirrorHistory says
          if (rough < 0.9f) EXPECT_LT(px, -1e5f) << "NoSpecReproj: TAA history at " << rough;
          else EXPECT_FLOAT_EQ(px, primary.prevX(x, 0)) << rough;
        } else if (rough < 0.02f && mirrors == SvgfTaaMirrorHistory::none) {
          EXPECT_LT(px, -1e5f) << "taaMirrorHistory=none: TAA history on a mirror pixel";
          EXPECT_EQ(taa.kind[size_t(x)], Reprojection::None);
        } else if (rough < 0.02f && mirrors == SvgfTaaMirrorHistory::primaryMotion) {
          EXPECT_FLOAT_EQ(px, primary.prevX(x, 0)) << "taaMirrorHistory=primaryMotion at " << rough;
        } else if (rough < 0.02f || (glossy && rough < 0.4f)) {
          EXPECT_NEAR(px, x + shift + 0.5f, 0.01f) << "not the reflection motion at " << rough;
        } else {
          EXPECT_FLOAT_EQ(px, primary.prevX(x, 0)) << "not the primary motion at " << rough;
        }
      }
    }
}

// ---------------------------------------------------------------- item 16: neighbourhood clipping

TEST(VoorhuisClipping, InjectedHistoryIsClippedOnNonDiffusePixelsOnly) {
  // Current frame: noise around 1 (range [0.5, 1.5]); history: 10 everywhere (a ghost).
  const int w = 24, h = 12;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.5f, 1.5f);
  Plane3 cur;
  resize(cur, w, h);
  for (auto& p : cur)
    for (float& v : p.data) v = u(rng);
  PixelVector<uint8_t> clip(size_t(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = w / 2; x < w; ++x) clip[size_t(y) * w + x] = 1;  // right half: roughness < 0.9
  Plane3 lo, hi, scratch;
  clipBox(cur, &clip, ClipBoxOptions{}, lo, hi, scratch);
  // The box is the 5x5 min / max of the 7x7-Gaussian-filtered frame: check one pixel against
  // a direct evaluation.
  float g[7];
  clipGaussianWeights(3, 1.5f, g);
  auto blurred = [&](int c, int x, int y) {
    double v = 0;
    for (int j = -3; j <= 3; ++j)
      for (int i = -3; i <= 3; ++i)
        v += g[i + 3] * g[j + 3] * cur[c](std::clamp(x + i, 0, w - 1), std::clamp(y + j, 0, h - 1));
    return v;
  };
  double mn = 1e9, mx = -1e9;
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      mn = std::min(mn, blurred(1, 17 + i, 5 + j));
      mx = std::max(mx, blurred(1, 17 + i, 5 + j));
    }
  EXPECT_NEAR(lo[1](17, 5), mn, 1e-5);
  EXPECT_NEAR(hi[1](17, 5), mx, 1e-5);
  EXPECT_TRUE(std::isinf(lo[0](3, 5)) && std::isinf(hi[0](3, 5)));

  // Accumulate with a history of 10 (many frames) and the box: clipped on the right only.
  const TestFrame still(w, h);
  const Reprojection rp = identity(still.f, still.f);
  TemporalAccumulator acc;
  acc.resize(w, h);
  Plane3 ghost;
  resize(ghost, w, h, 10.0f);
  for (int k = 0; k < 30; ++k) acc.run(k ? rp : noHistory(still.f), ghost, 0.1f, 0.1f, 255);
  AccumulationOptions opt;
  opt.clipLow = &lo;
  opt.clipHigh = &hi;
  acc.run(rp, cur, 0.1f, 0.1f, 255, opt);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = acc.color()[c](x, y);
        if (x >= w / 2) {  // within one frame the ghost is gone: history clipped into the box
          EXPECT_LE(v, 0.1f * cur[c](x, y) + 0.9f * hi[c](x, y) + 1e-5f);
          EXPECT_LT(v, 1.6f);
        } else {
          EXPECT_NEAR(v, 0.1f * cur[c](x, y) + 0.9f * 10.0f, 1e-4f);  // diffuse: untouched
        }
      }
}

// The own-surface box of pixel (x, y), channel c, evaluated directly in double precision: the
// edge-clamped Gaussian over the taps of each pixel's own key, at the window's pixels of
// (x, y)'s key; returns its {min, max}.
std::pair<double, double> ownSurfaceBoxReference(const Plane3& cur, const PixelVector<uint32_t>& key, int c, int x,
                                                 int y) {
  const ClipBoxOptions opt;
  const int R = opt.gaussianRadius, W = opt.windowRadius, w = cur[0].width, h = cur[0].height;
  std::vector<float> g(size_t(2 * R + 1));
  clipGaussianWeights(R, opt.sigma, g.data());
  auto blurred = [&](int px, int py) {
    const uint32_t k = key[size_t(py) * w + px];
    double v = 0, sum = 0;
    for (int j = -R; j <= R; ++j)
      for (int i = -R; i <= R; ++i) {
        const int qx = std::clamp(px + i, 0, w - 1), qy = std::clamp(py + j, 0, h - 1);
        if (key[size_t(qy) * w + qx] != k) continue;
        v += double(g[size_t(i + R)]) * g[size_t(j + R)] * cur[c](qx, qy);
        sum += double(g[size_t(i + R)]) * g[size_t(j + R)];
      }
    return v / sum;
  };
  const uint32_t k = key[size_t(y) * w + x];
  double mn = 1e9, mx = -1e9;
  for (int qy = std::max(0, y - W); qy <= std::min(h - 1, y + W); ++qy)
    for (int qx = std::max(0, x - W); qx <= std::min(w - 1, x + W); ++qx) {
      if (key[size_t(qy) * w + qx] != k) continue;
      mn = std::min(mn, blurred(qx, qy));
      mx = std::max(mx, blurred(qx, qy));
    }
  return {mn, mx};
}

// The clipping neighbourhood restricted to the pixel's own surface (SvgfSettings::clipOwnSurface,
// docs/methods/reflections.md "Neighbourhood clipping at silhouettes"). A specular disc of
// constant demodulated colour 1 against a background whose specular lobe is black (a diffuse
// wall): over every pixel of the window the box of a rim pixel is pulled down by the black
// background, so a converged history of 1 is clipped darker; over its own surface it is [1, 1].
TEST(VoorhuisClipping, OwnSurfaceBoxDoesNotCrossASilhouette) {
  const int w = 32, h = 24;
  Plane3 cur;
  resize(cur, w, h, 0.0f);
  PixelVector<uint8_t> clip(size_t(w) * h, 0);
  PixelVector<uint32_t> key(size_t(w) * h, 0);
  auto inDisc = [](int x, int y) { return (x - 15.5) * (x - 15.5) + (y - 11.5) * (y - 11.5) < 36.0; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!inDisc(x, y)) continue;
      const size_t i = size_t(y) * w + x;
      clip[i] = 1;
      key[i] = 4u * 7u + uint32_t(SurfaceClass::GlossyReflection);  // object 7
      for (auto& p : cur) p.data[i] = 1.0f;
    }
  Plane3 lo, hi, scratch, loAll, hiAll;
  clipBox(cur, &clip, ClipBoxOptions{}, lo, hi, scratch, &key);
  clipBox(cur, &clip, ClipBoxOptions{}, loAll, hiAll, scratch);
  double lowestTop = 1.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        if (!inDisc(x, y)) {  // not clipped either way
          EXPECT_TRUE(std::isinf(lo[c](x, y)) && lo[c](x, y) < 0 && std::isinf(hi[c](x, y)) && hi[c](x, y) > 0);
          continue;
        }
        EXPECT_NEAR(lo[c](x, y), 1.0f, 1e-6f) << x << "," << y;
        EXPECT_NEAR(hi[c](x, y), 1.0f, 1e-6f) << x << "," << y;
        lowestTop = std::min(lowestTop, double(hiAll[c](x, y)));
      }
  // The whole window: the rim's box top is dragged towards the black, so a history of 1 is
  // clipped darker (measured 0.943; the window's inner pixels keep it from falling further).
  EXPECT_LT(lowestTop, 0.97);

  // Two specular objects side by side, same class, colours 1 and 3, told apart by the object id
  // in the key: with the key each box holds its own colour; a direct evaluation of the masked
  // Gaussian and window (double) at a pixel next to the seam agrees.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.2f, 0.2f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const bool right = x >= w / 2;
      clip[i] = 1;
      key[i] = 4u * (right ? 2u : 1u) + uint32_t(SurfaceClass::Mirror);
      for (auto& p : cur) p.data[i] = (right ? 3.0f : 1.0f) + u(rng);
    }
  clipBox(cur, &clip, ClipBoxOptions{}, lo, hi, scratch, &key);
  for (int x : {w / 2 - 1, w / 2, 3}) {
    const int y = 10, c = 1;
    const auto [mn, mx] = ownSurfaceBoxReference(cur, key, c, x, y);
    EXPECT_NEAR(lo[c](x, y), mn, 1e-5) << x;
    EXPECT_NEAR(hi[c](x, y), mx, 1e-5) << x;
    const float own = x >= w / 2 ? 3.0f : 1.0f;
    EXPECT_GT(lo[c](x, y), own - 0.25f) << x;  // the other object's colour is not in the box
    EXPECT_LT(hi[c](x, y), own + 0.25f) << x;
  }
  EXPECT_THROW(clipBox(cur, nullptr, ClipBoxOptions{}, lo, hi, scratch, &key), Error);
}

// The own-surface box at every pixel against a direct evaluation in double precision, on
// random patches of keys (some clipped, some not: a key's pixels are all one or the other), on
// frames narrower than the prefilter, as wide, and wider: the border columns and the interior
// (computed for whole rows at once) alike.
TEST(VoorhuisClipping, OwnSurfaceBoxMatchesADirectEvaluationEverywhere) {
  std::mt19937 rng(11);
  for (auto [w, h] : {std::pair{1, 1}, {5, 3}, {7, 9}, {37, 23}}) {
    Plane3 cur;
    resize(cur, w, h, 0.0f);
    PixelVector<uint8_t> clip(size_t(w) * h, 0);
    PixelVector<uint32_t> key(size_t(w) * h, 0);
    std::uniform_int_distribution<int> patch(0, 5);
    std::uniform_real_distribution<float> value(0.0f, 4.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        // 3x2-pixel cells of six keys; keys 0 and 1 are not clipped.
        key[i] = uint32_t((x / 3 + 2 * (y / 2) + patch(rng) / 5) % 6);
        clip[i] = key[i] >= 2;
        for (auto& p : cur) p.data[i] = value(rng);
      }
    Plane3 lo, hi, scratch;
    clipBox(cur, &clip, ClipBoxOptions{}, lo, hi, scratch, &key);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          if (!clip[size_t(y) * w + x]) {
            EXPECT_TRUE(std::isinf(lo[c](x, y)) && lo[c](x, y) < 0 && std::isinf(hi[c](x, y)) && hi[c](x, y) > 0);
            continue;
          }
          const auto [mn, mx] = ownSurfaceBoxReference(cur, key, c, x, y);
          EXPECT_NEAR(lo[c](x, y), mn, 1e-5 * mx) << w << "x" << h << " at " << x << "," << y;
          EXPECT_NEAR(hi[c](x, y), mx, 1e-5 * mx) << w << "x" << h << " at " << x << "," << y;
        }
  }
}

TEST(VoorhuisClipping, SurfaceKeysSeparateClassesAndObjects) {
  TestFrame t(4, 1);
  t.set(Buffer::ObjectId, 0.0f);
  const float ids[4] = {3, 3, 4, -1};
  for (int x = 0; x < 4; ++x) t.p(Buffer::ObjectId)(x, 0) = ids[x];
  PixelVector<uint8_t> cls(4);
  cls[0] = uint8_t(SurfaceClass::Mirror);
  cls[1] = uint8_t(SurfaceClass::GlossyReflection);
  cls[2] = uint8_t(SurfaceClass::GlossyReflection);
  cls[3] = uint8_t(SurfaceClass::GlossyReflection);
  PixelVector<uint32_t> k;
  surfaceKeys(t.f, cls, k);
  EXPECT_NE(k[0], k[1]);  // same object, another class
  EXPECT_NE(k[1], k[2]);  // same class, another object
  EXPECT_NE(k[2], k[3]);
  EXPECT_NE(k[1], k[3]);
  t.f.buffers[int(Buffer::ObjectId)].clear();  // no object ids: the class alone
  surfaceKeys(t.f, cls, k);
  EXPECT_NE(k[0], k[1]);
  EXPECT_EQ(k[1], k[2]);
  EXPECT_EQ(k[2], k[3]);
}

// Item 16(c): a glossy surface (0.4 <= roughness < 0.9 keeps the primary motion) under a camera
// panning sideways. Its highlight (a reflection) moves 2 px a frame while the surface moves 1, so
// the primary reprojection drags the highlight's history behind it: a ghost trail. The trail is
// measured against the same region ahead of the highlight (the spatial filter spreads the
// highlight symmetrically, ghosting only backwards), through the whole SVGF Voorhuis pipeline.
struct GlossyPan {
  double trail = 0, ahead = 0;  // mean luminance behind / ahead of the highlight, last frame
};
GlossyPan panGlossyHighlight(float roughness, bool clipping) {
  const int w = 72, h = 16, frames = 16;
  const float background = 0.2f, peak = 5.0f, sigma = 1.5f;
  auto device = Device::create();
  auto d = device->createDenoiser("svgf");
  d->set("variant", "voorhuis");
  d->set("taa", "false");  // the accumulation's ghost alone
  d->set("neighbourhoodClipping", clipping ? "on" : "off");
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> noise(0.8f, 1.2f);
  Image out(w, h, 3);
  GlossyPan r;
  for (int t = 0; t < frames; ++t) {
    const float cx = 8.0f + 2.0f * t, cy = 8.0f;
    Frame f;
    f.number = t + 1;
    f.width = w;
    f.height = h;
    f[Buffer::Color] = Image(w, h, 3);
    f[Buffer::Albedo] = Image(w, h, 3, 1.0f);
    f[Buffer::Normal] = Image(w, h, 3);
    f[Buffer::Depth] = Image(w, h, 1, 2.0f);
    f[Buffer::Position] = Image(w, h, 3);
    f[Buffer::Motion] = Image(w, h, 2);
    f[Buffer::Roughness] = Image(w, h, 1, roughness);
    f[Buffer::Metalness] = Image(w, h, 1, 1.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float dx = float(x) - cx, dy = float(y) - cy;
        const float v = (background + peak * std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma))) * noise(rng);
        for (int c = 0; c < 3; ++c) f[Buffer::Color].at(x, y, c) = v;
        f[Buffer::Normal].at(x, y, 2) = 1.0f;
        // The surface point now at x was at x - 1 (the camera pans: content moves right).
        f[Buffer::Position].at(x, y, 0) = 0.01f * float(x - t);
        f[Buffer::Position].at(x, y, 1) = -0.01f * float(y);
        f[Buffer::Position].at(x, y, 2) = -2.0f;
        f[Buffer::Motion].at(x, y, 0) = -1.0f;
      }
    d->denoise(f.inputs(), out.view());
    if (t != frames - 1) continue;
    int n = 0;
    for (int y = 4; y < 12; ++y)
      for (int k = 6; k <= 16; ++k) {
        r.trail += out.at(int(cx) - k, y, 1);
        r.ahead += out.at(int(cx) + k, y, 1);
        ++n;
      }
    r.trail /= n;
    r.ahead /= n;
  }
  return r;
}

TEST(VoorhuisClipping, GlossyGhostingUnderCameraMotionIsReduced) {
  for (float roughness : {0.4f, 0.6f, 0.85f}) {
    const GlossyPan off = panGlossyHighlight(roughness, false), on = panGlossyHighlight(roughness, true);
    const double ghostOff = off.trail - off.ahead, ghostOn = on.trail - on.ahead;
    std::printf("roughness %.2f: ghost (trail - ahead) %.4f without clipping, %.4f with\n", roughness, ghostOff, ghostOn);
    // Without clipping the trail holds a sizeable part of the highlight (alpha 0.1 on specular
    // pixels); with it, the history is clamped into the box of the current frame there. Measured
    // (all three roughnesses are the Glossy class): 0.143 without, 0.024 with, i.e. a sixth;
    // what is left lies next to the highlight, whose blurred tail is inside the 5x5 box.
    // Bound: a quarter.
    EXPECT_GT(ghostOff, 0.1) << roughness;
    EXPECT_LT(std::abs(ghostOn), 0.25 * ghostOff) << roughness;
  }
  // Diffuse pixels (roughness >= 0.9) are not clipped: the same ghost either way.
  const GlossyPan off = panGlossyHighlight(0.95f, false), on = panGlossyHighlight(0.95f, true);
  EXPECT_NEAR(on.trail - on.ahead, off.trail - off.ahead, 1e-6);
  EXPECT_GT(off.trail - off.ahead, 0.05);
}

// ---------------------------------------------------------------- item 15: Eq. 6

TEST(VoorhuisBandwidth, Eq6SigmaAndFalloff) {
  EXPECT_FLOAT_EQ(glossySpatialSigma(0.0f, 0.5f), 1.0f);  // no footprint: sigma 1
  EXPECT_NEAR(glossySpatialSigma(0.5f, 0.5f), std::exp(-1.0f), 1e-7);
  EXPECT_LT(glossySpatialSigma(1.0f, 0.5f), glossySpatialSigma(0.2f, 0.5f));  // larger footprint, smaller sigma
  EXPECT_FLOAT_EQ(glossySpatialFalloff(1.0f), 0.0f);  // sigma 1 leaves the B3 kernel unchanged
  EXPECT_NEAR(glossySpatialFalloff(0.5f), 1.5f, 1e-6);
}

// Eq. 6 with omega in widths of the reflected lobe (SvgfSettings::bandwidthPerLobe): the falloff
// c of a glossy pixel follows from sigma = exp(-footprint / (omega 2 roughness^2 t)); it is the
// same when the scene is modelled in other units (positions and footprint x 100), unlike the
// paper's world-unit omega; a rougher lobe narrows less; a mirror ray into the sky not at all.
std::vector<float> falloffValues(float roughness, float scale, bool perLobe, bool sky = false) {
  TestFrame t(6, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      for (int k = 0; k < 3; ++k) t.p(Buffer::Position, k)(x, y) *= scale;
  t.set(Buffer::Roughness, roughness);
  t.set(Buffer::ReflectedFootprint, 0.04f * scale);
  t.set(Buffer::ReflectedNormal, 0.0f);
  t.set(Buffer::ReflectedPosition, 0.0f);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      for (int k = 0; k < 3; ++k) t.p(Buffer::ReflectedPosition, k)(x, y) = t.p(Buffer::Position, k)(x, y);
      t.p(Buffer::ReflectedPosition, 2)(x, y) += 2.0f * scale;  // the hit 2 (x scale) away
      t.p(Buffer::ReflectedNormal, 2)(x, y) = sky ? 0.0f : -1.0f;
    }
  SvgfSettings s = ours();
  s.bandwidthPerLobe = perLobe;
  const svgf::ReflectionParts parts = svgf::resolveReflectionParts(s, [&](Buffer b) { return t.f.has(b); }, false);
  EXPECT_TRUE(parts.glossyBandwidth);
  svgf::Reflections refl;
  refl.resize(6, 4, 2);
  refl.prepare(t.f, nullptr, s, parts, false, noHistory(t.f));
  std::vector<float> v;
  refl.forEachPlane([&](std::string_view name, const float* data, size_t n) {
    if (name != "Eq. 6 falloff") return;
    for (size_t i = 0; i < n; ++i)
      if (data[i] != 0.0f) v.push_back(data[i]);
  });
  return v;
}

TEST(VoorhuisBandwidth, OmegaInLobeWidthsIsScaleFreeAndFollowsTheRoughness) {
  EXPECT_FLOAT_EQ(svgf::reflectedLobeWidth(0.1f, 5.0f), 2.0f * 0.01f * 5.0f);
  EXPECT_GT(svgf::reflectedLobeWidth(0.0f, 1.0f), 0.0f);  // omega stays positive

  const double sigma = std::exp(-0.04 / (0.5 * 2 * 0.1 * 0.1 * 2));  // e^-2
  const double c = 0.5 / (sigma * sigma) - 0.5;
  for (float scale : {1.0f, 100.0f}) {
    const std::vector<float> v = falloffValues(0.1f, scale, true);
    ASSERT_EQ(v.size(), 24u) << scale;  // every pixel is glossy (0.02 <= 0.1 < 0.4)
    for (float f : v) EXPECT_NEAR(f, c, 1e-3 * c) << scale;
  }
  // World units: the same scene in centimetres narrows the kernel to the clamp.
  const std::vector<float> m = falloffValues(0.1f, 1.0f, false), cm = falloffValues(0.1f, 100.0f, false);
  ASSERT_FALSE(m.empty());
  ASSERT_FALSE(cm.empty());
  EXPECT_NEAR(m[0], 0.5 / std::exp(-2 * 0.04 / 0.5) - 0.5, 1e-4);
  EXPECT_GT(cm[0], 1000.0f * m[0]);
  // A rougher lobe (0.3: nine times as wide) spreads over the footprint: a smaller falloff.
  const std::vector<float> rough = falloffValues(0.3f, 1.0f, true);
  ASSERT_FALSE(rough.empty());
  EXPECT_LT(rough[0], 0.1f * c);
  // The mirror ray escapes (zero reflected normal): no narrowing.
  EXPECT_TRUE(falloffValues(0.1f, 1.0f, true, true).empty());
}

// One a-trous level's guide and images over a flat surface: every pixel at `depth` with the
// normal along `axis`.
struct FlatLevel {
  AtrousGuide g;
  AtrousImage in, out;
  FlatLevel(int w, int h, int pad, float depth, int axis) {
    g.resize(w, h, pad);
    in.resize(w, h, pad);
    out.resize(w, h, pad);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        g.depth.at(x, y) = depth;
        g.normal[axis].at(x, y) = 1.0f;
      }
  }
};

TEST(VoorhuisBandwidth, FalloffNarrowsTheAtrousFootprint) {
  // Impulse response of one level on flat features with w_l off: its spatial variance (in
  // kernel units) is that of the B3 spline, 2 * 1 = 2 over both axes, at c = 0 and shrinks
  // like 2 sigma^2 as Eq. 6's sigma falls.
  const int w = 32, h = 32, pad = 8;
  FlatLevel level(w, h, pad, 2.0f, 2);
  const AtrousGuide& g = level.g;
  AtrousImage &in = level.in, &out = level.out;
  PaddedPlane off, fall;
  off.resize(w, h, pad);
  fall.resize(w, h, pad);
  double last = 1e9;
  for (float sigma : {1.0f, 0.8f, 0.5f, 0.3f}) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) fall.at(x, y) = glossySpatialFalloff(sigma);
    // The response at p to an impulse at q equals the weight of q in p's kernel: spread a
    // unit impulse and read the weights around it (all pixels share one falloff).
    for (auto& c : in.color) c.clear();
    in.color[0].at(16, 16) = 1.0f;
    AtrousLevel lv;
    lv.step = 2;
    lv.sigmaScale = &off;  // 0: w_l off
    lv.spatialFalloff = &fall;
    atrousLevel(g, lv, in, out);
    double sum = 0, m2 = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double v = out.color[0].at(x, y), kx = (x - 16) / 2.0, ky = (y - 16) / 2.0;
        sum += v;
        m2 += v * (kx * kx + ky * ky);
      }
    const double var = m2 / sum;
    if (sigma == 1.0f) {
      EXPECT_NEAR(var, 2.0, 1e-4);
    } else if (sigma >= 0.5f) {
      EXPECT_NEAR(var, 2.0 * sigma * sigma, 0.25 * 2.0 * sigma * sigma);
    }
    // (Below ~0.5 the integer taps make the spread fall faster than the continuous 2 sigma^2.)
    EXPECT_LT(var, last + 1e-9);
    last = var;
  }
}

// ---------------------------------------------------------------- items 5, 6: pure speculars

// The reflected guide's key (AtrousLevel::surfaceKey, "Mirror pixels keyed apart" in
// docs/methods/reflections.md): a mirror region (key 1) inside a surface (key 0) whose
// features are identical to the mirror's (the worst case: nothing else tells them apart) and
// whose illumination differs. Every level, at steps up to 16 (wider than the region), leaves
// both exactly at their own value, on every CPU path; without the key they mix.
TEST(VoorhuisMirrors, KeyedMirrorPixelsTakeNothingFromTheSurfaceAround) {
  const int w = 64, h = 48, pad = 40;
  FlatLevel level(w, h, pad, 3.0f, 1);
  const AtrousGuide& g = level.g;
  AtrousImage &in = level.in, &out = level.out;
  PaddedPlane key;
  key.resize(w, h, pad);
  auto mirror = [](int x, int y) { return x >= 20 && x < 32 && y >= 16 && y < 28; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      key.at(x, y) = mirror(x, y) ? 1.0f : 0.0f;
      const float v = mirror(x, y) ? 2.0f : 0.25f;
      for (auto& c : in.color) c.at(x, y) = v;
      in.lum.at(x, y) = v;
      in.var.at(x, y) = 1.0f;  // wide w_l: luminance would not keep them apart either
    }
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath scoped(path);
    for (int step : {1, 4, 16})
      for (bool keyed : {true, false}) {
        AtrousLevel lv;
        lv.step = step;
        lv.sigmaLuminance = 1e6f;
        lv.surfaceKey = keyed ? &key : nullptr;
        atrousLevel(g, lv, in, out);
        double worst = 0;
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            worst = std::max(worst, std::fabs(double(out.color[1].at(x, y)) - (mirror(x, y) ? 2.0 : 0.25)));
        if (keyed)
          EXPECT_LT(worst, 1e-6) << cpuPathName(path) << " step " << step;
        else
          EXPECT_GT(worst, 0.1) << cpuPathName(path) << " step " << step << ": the test needs the key";
      }
  }
}

// A mirror (every pixel, roughness 0) showing a checkerboard on a surface at two depths: the
// left half reflects a near wall, the right half a far one, with different illumination.
struct MirrorScene {
  TestFrame t;
  explicit MirrorScene(int w, int h) : t(w, h) {
    t.set(Buffer::Roughness, 0.0f);
    t.set(Buffer::Metalness, 1.0f);
    t.set(Buffer::ReflectedPosition, 0.0f);
    t.set(Buffer::ReflectedNormal, 0.0f);
    t.set(Buffer::ReflectedAlbedo, 0.0f);
    t.set(Buffer::MirrorDirection, 0.0f);
    t.set(Buffer::SecondaryDistance, 0.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool far = x >= w / 2;
        const float dist = far ? 6.0f : 1.0f;
        t.p(Buffer::SecondaryDistance)(x, y) = dist;
        t.p(Buffer::MirrorDirection, 2)(x, y) = -1.0f;
        for (int k = 0; k < 3; ++k) t.p(Buffer::ReflectedPosition, k)(x, y) = t.p(Buffer::Position, k)(x, y);
        t.p(Buffer::ReflectedPosition, 2)(x, y) = -2.0f - dist;
        t.p(Buffer::ReflectedNormal, 2)(x, y) = 1.0f;
        const float checker = ((x / 2 + y / 2) & 1) ? 0.9f : 0.1f;
        for (int c = 0; c < 3; ++c) {
          t.p(Buffer::Albedo, c)(x, y) = 0.8f;
          t.p(Buffer::ReflectedAlbedo, c)(x, y) = checker;
        }
      }
  }
  // Noise-free radiance: albedo x reflected albedo x illumination (2 near, 0.5 far).
  void shade(std::mt19937* noise) {
    std::uniform_real_distribution<float> u(0.0f, 2.0f);
    for (int y = 0; y < t.h; ++y)
      for (int x = 0; x < t.w; ++x) {
        const float light = (x >= t.w / 2 ? 0.5f : 2.0f) * (noise ? u(*noise) : 1.0f);
        for (int c = 0; c < 3; ++c)
          t.p(Buffer::Color, c)(x, y) = t.p(Buffer::Albedo, c)(x, y) * t.p(Buffer::ReflectedAlbedo, c)(x, y) * light;
      }
  }
};

Image toImage(const FrameData& f, Buffer b) {
  Image im(f.width, f.height, bufferChannelCount(b));
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      for (int c = 0; c < bufferChannelCount(b); ++c) im.at(x, y, c) = f.plane(b, c)(x, y);
  return im;
}

Frame toFrame(const FrameData& f) {
  Frame out;
  out.width = f.width;
  out.height = f.height;
  for (int b = 0; b < kBufferCount; ++b)
    if (f.has(Buffer(b))) out[Buffer(b)] = toImage(f, Buffer(b));
  return out;
}

Image denoiseOnce(const Frame& frame, SvgfSettings s) {
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  s.taa.taa = false;
  auto d = device->createDenoiser(s);
  Image out(frame.width, frame.height, 3);
  d->denoise(frame.inputs(), out.view());
  return out;
}

TEST(VoorhuisMirrors, DemodulationByPrimaryTimesReflectedAlbedoKeepsReflectedTexture) {
  // Noise-free: with the reflected albedo divided out the illumination is piecewise constant,
  // a fixed point of the filter, so the output equals the input (demodulate -> remodulate is
  // the identity). With the primary albedo only, the checker is filtered and blurred.
  MirrorScene m(32, 16);
  m.shade(nullptr);
  const Frame f = toFrame(m.t.f);
  SvgfSettings s = ours();
  s.reflectedFeatures = SvgfPart::on;
  const Image a = denoiseOnce(f, s);
  s.reflectedFeatures = SvgfPart::off;
  const Image b = denoiseOnce(f, s);
  double errA = 0, errB = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c) {
        errA = std::max(errA, double(std::fabs(a.at(x, y, c) - f[Buffer::Color].at(x, y, c))));
        errB = std::max(errB, double(std::fabs(b.at(x, y, c) - f[Buffer::Color].at(x, y, c))));
      }
  EXPECT_LT(errA, 1e-4);
  EXPECT_GT(errB, 0.05);
}

TEST(VoorhuisMirrors, ReflectedDepthEdgeStaysSharp) {
  // Noisy illumination; the reflection has a depth edge at x = w/2 (near wall | far wall)
  // where the primary features are flat. Stopping on the reflected features keeps the two
  // illumination levels apart; the primary features let them mix across the edge.
  const int w = 48, h = 24;
  MirrorScene m(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) m.t.p(Buffer::ReflectedAlbedo, c)(x, y) = 0.5f;  // no texture
  std::mt19937 rng(7);
  m.shade(&rng);
  const Frame f = toFrame(m.t.f);
  SvgfSettings s = ours();
  s.reflectedFeatures = SvgfPart::on;
  const Image a = denoiseOnce(f, s);
  s.reflectedFeatures = SvgfPart::off;
  const Image b = denoiseOnce(f, s);
  // Mean of the column just right of the edge (far side, expected 0.8 * 0.5 * 0.5 = 0.2).
  auto column = [&](const Image& im, int x) {
    double v = 0;
    for (int y = 4; y < h - 4; ++y) v += im.at(x, y, 1);
    return v / (h - 8);
  };
  const double expected = 0.8 * 0.5 * 0.5;
  EXPECT_LT(std::fabs(column(a, w / 2) - expected), 0.3 * expected) << "reflected features";
  EXPECT_GT(std::fabs(column(b, w / 2) - expected), 0.6 * expected) << "primary features should blur the edge";
}

// ---------------------------------------------------------------- which parts run

TEST(VoorhuisParts, InputWithoutReflectionFeaturesRunsWhatItCanAndSaysWhy) {
  // Blender-like input: colour split into diffuse / specular lobes, no roughness, no
  // reflection buffers. voorhuis runs clipping and per-class alpha on the specular lobe.
  auto has = [](Buffer b) {
    return b == Buffer::Color || b == Buffer::Normal || b == Buffer::Depth || b == Buffer::Albedo ||
           b == Buffer::Diffuse || b == Buffer::Specular || b == Buffer::Position;
  };
  const svgf::ReflectionParts p = svgf::resolveReflectionParts(ours(), has, true);
  EXPECT_TRUE(p.clipping);
  EXPECT_TRUE(p.materialAlpha);
  EXPECT_EQ(p.motion, SpecularMotion::Primary);
  EXPECT_FALSE(p.reflectedFeatures);
  EXPECT_FALSE(p.glossyBandwidth);
  std::string all;
  for (const auto& n : p.notes) all += n + "\n";
  EXPECT_NE(all.find("reflection motion (mirrors) off: the frame has no 'roughness' buffer"), std::string::npos) << all;
  EXPECT_NE(all.find("reflectedFeatures off"), std::string::npos) << all;
  EXPECT_NE(all.find("glossyBandwidth off"), std::string::npos) << all;
  // Without the lobe split nothing can be classed: those parts are off too, with a reason.
  const svgf::ReflectionParts q = svgf::resolveReflectionParts(ours(), has, false);
  EXPECT_FALSE(q.clipping);
  EXPECT_FALSE(q.classes);
  // A part asked for explicitly is an error naming the missing buffer.
  auto expectError = [](const SvgfSettings& s, auto has, const char* buffer) {
    try {
      svgf::resolveReflectionParts(s, has, true);
      ADD_FAILURE() << "expected an error naming " << buffer;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(buffer), std::string::npos) << e.what();
    }
  };
  SvgfSettings s = ours();
  s.reflectedFeatures = SvgfPart::on;
  expectError(s, has, "'roughness'");
  s = ours();
  s.specularMotion = SvgfSpecularMotion::reflection;
  expectError(s, [&](Buffer b) { return has(b) || b == Buffer::Roughness; }, "'reflectedPosition'");
}

TEST(VoorhuisParts, DenoiserReportsOffPartsInItsStatistics) {
  MirrorScene m(16, 8);
  m.shade(nullptr);
  Frame f = toFrame(m.t.f);
  f[Buffer::ReflectedFootprint] = Image();  // absent
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto d = device->createDenoiser("svgf");
  d->set("variant", "voorhuis");
  Image out(16, 8, 3);
  d->denoise(f.inputs(), out.view());
  ASSERT_EQ(d->stats().notes.size(), 1u);
  EXPECT_EQ(d->stats().notes[0], "glossyBandwidth off: the frame has no 'reflectedFootprint' buffer");
  d->set("glossyBandwidth", "on");
  EXPECT_THROW(d->denoise(f.inputs(), out.view()), Error);
}

// The parts' per-frame state (classes, specular record, per-class alpha, clip boxes) belongs to
// the frame that computed it: after switching to a preset without them, a denoiser runs as
// one that never had them, frame for frame.
TEST(VoorhuisParts, SwitchingThePartsOffLeavesNoneOfTheirStateBehind) {
  MirrorScene m(16, 8);
  m.shade(nullptr);
  Frame f = toFrame(m.t.f);
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto switched = device->createDenoiser("svgf");
  switched->set("variant", "voorhuis");
  Image a(16, 8, 3);
  for (int i = 0; i < 3; ++i) switched->denoise(f.inputs(), a.view());
  switched->set("variant", "voorhuisBase");
  switched->reset();
  auto fresh = device->createDenoiser("svgf");
  fresh->set("variant", "voorhuisBase");
  test::expectRunsAsFresh(*switched, *fresh, {f, f, f});
}

// The parts' per-frame planes exist only once their part has run (Reflections::resize): plain
// SVGF keeps none of them (they were ~30 full-frame planes), and a denoiser that switches the
// parts on mid-sequence, allocating them then, runs as one that had them from the start.
TEST(VoorhuisParts, PlanesOfThePartsAreKeptOnlyOnceThePartsRun) {
  MirrorScene m(16, 8);
  m.shade(nullptr);
  Frame f = toFrame(m.t.f);
  const std::string_view parts[] = {"virtual depth", "reflected normal", "virtual depth gradient", "Eq. 6 falloff",
                                    "mirror key", "blend floor", "stream albedo", "clip low", "clip high",
                                    "clip prefilter"};
  auto device = Device::create({.backend = Backend::Cpu, .threads = 1});
  auto switched = device->createDenoiser("svgf");
  Image a(16, 8, 3);
  for (int i = 0; i < 3; ++i) switched->denoise(f.inputs(), a.view());
  for (std::string_view p : parts) EXPECT_EQ(test::floatsKept(*switched, p), 0u) << p << " kept by plain SVGF";
  switched->set("variant", "voorhuis");
  switched->reset();
  auto fresh = device->createDenoiser("svgf");
  fresh->set("variant", "voorhuis");
  test::expectRunsAsFresh(*switched, *fresh, {f, f, f});
  // The parts that ran now hold their planes at the frame's size.
  EXPECT_EQ(test::floatsKept(*switched, "virtual depth"), 16u * 8u);
  EXPECT_EQ(test::floatsKept(*switched, "reflected normal"), 3u * 16u * 8u);
  EXPECT_EQ(test::floatsKept(*switched, "blend floor"), 16u * 8u);
  EXPECT_EQ(test::floatsKept(*switched, "clip low"), 3u * 16u * 8u);
  EXPECT_GT(test::floatsKept(*switched, "mirror key"), 16u * 8u);  // padded
}

}  // namespace
}  // namespace rtd
