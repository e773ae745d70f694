// The shared TAA pass (Karis 2014): fixed points, exact reprojection of a shifted image, the
// YCoCg neighbourhood clamp (box and box + cross) and the blend, on hand-computed values, in the
// linear and the display domain (rtd/methods/taa.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>
#include <string>

#include "passes/taa.h"
#include "passes/tonemap.h"
#include "support/cpu_paths.h"
#include "support/taa_frames.h"

namespace rtd {
namespace {

constexpr int kW = 23, kH = 17;

TaaSettings settings(float alpha, TaaDomain domain = TaaDomain::linear,
                     TaaNeighbourhood shape = TaaNeighbourhood::box3x3,
                     TaaHistoryFilter filter = TaaHistoryFilter::bilinear) {
  TaaSettings s;
  s.taaAlpha = alpha;
  s.taaSubpixelAlpha = 0.0f;  // Karis's constant alpha (its rise: Taa.SubpixelAlphaRaisesTheBlendWeightByTheFetchVariance)
  s.taaDomain = domain;
  s.taaNeighbourhood = shape;
  s.taaHistoryFilter = filter;
  return s;
}
TaaSettings catmullRom(float alpha, TaaDomain domain = TaaDomain::linear) {
  return settings(alpha, domain, TaaNeighbourhood::box3x3, TaaHistoryFilter::catmullRom);
}
constexpr TaaHistoryFilter kFilters[] = {TaaHistoryFilter::bilinear, TaaHistoryFilter::catmullRom};
const char* name(TaaHistoryFilter f) { return f == TaaHistoryFilter::bilinear ? "bilinear" : "catmullRom"; }

// The reprojection record of a frame whose every history tap passes the consistency tests (as
// reproject() writes it; Catmull-Rom needs it, see Taa.CatmullRomReproducesAQuadraticAndFallsBackToBilinearOnRejectedTaps).
void acceptAll(Reprojection& rp) {
  for (int y = 0; y < rp.height; ++y)
    for (int x = 0; x < rp.width; ++x)
      setBilinear(rp, size_t(y) * rp.width + x, rp.prevX(x, y), rp.prevY(x, y), [](int, int) { return true; });
}

// Every pixel's history comes from (x + shiftX, y), every tap accepted.
Reprojection shifted(float shiftX) { return test::shiftedReprojection(kW, kH, shiftX, 0.0f); }
template <class F> Plane3 image(F f) { return test::imageOf(kW, kH, f); }

// In both domains; HDR values (up to 20) in the display one, to the precision of the
// encoding near 1 (tonemap.h: about 2^-23 (1 + x) relative).
TEST(Taa, ConstantImageIsAFixedPoint) {
  const Plane3 in = image([](int, int, int c) { return 0.2f + 0.3f * c; });
  const Plane3 hdr = image([](int, int, int c) { return 0.05f + 10.0f * c; });
  for (TaaHistoryFilter filter : kFilters)
  for (TaaDomain d : {TaaDomain::linear, TaaDomain::display})
    for (const Plane3* img : {&in, &hdr}) {
      Taa taa;
      Plane3 out;
      const Reprojection rp = shifted(0.37f);  // border pixels' footprints cross the border
      for (int f = 0; f < 4; ++f) out = taa.run(rp, *img, settings(0.1f, d, TaaNeighbourhood::box3x3, filter));
      const float top = img == &hdr ? 20.05f : 0.8f;  // the largest channel sets the rounding
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < out[c].size(); ++i) {
          const float v = (*img)[c].data[i];
          EXPECT_NEAR(out[c].data[i], v, 1e-6f * (1 + top) * (1 + top)) << "domain " << int(d) << " " << name(filter);
        }
    }
}

// The display domain's vector encode and decode (passes/taa_simd.cpp) on every CPU path: a
// static image whose pixels span 1e-6 to 1e4 comes back within a few float roundings in the
// encoded domain (where the blend and the YCoCg clamp work; the encoding resolves 2^-24 near 1).
TEST(Taa, DisplayDomainIsAFixedPointOnEveryCpuPath) {
  const Plane3 in = image([](int x, int y, int c) { return std::pow(10.0f, -6.0f + 10.0f * float((x * 3 + y * 7 + c) % 41) / 40.0f); });
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    Taa taa;
    Plane3 out;
    const Reprojection rp = shifted(0.0f);
    for (int f = 0; f < 3; ++f) out = taa.run(rp, in, settings(0.1f, TaaDomain::display));
    double worst = 0;
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < out[c].size(); ++i) {
        const double e = std::sqrt(double(in[c].data[i]) / (1.0 + in[c].data[i]));
        worst = std::max(worst, std::abs(tonemap::taaEncode(out[c].data[i]) - e) / 0x1p-24);
      }
    EXPECT_LE(worst, 8.0) << cpuPathName(path);  // in units of 2^-24
    RecordProperty(std::string("worst_") + cpuPathName(path), std::to_string(worst));
  }
}

// The vector encode (sqrt(q) as q times its reciprocal square root) at 0, where the estimate is
// infinite, on every CPU path: a black image stays exactly black (its history is its own
// encoding, 0, not NaN); beside pixels of the smallest stored magnitude (kTiny, core/flush.h)
// and of the radiance bound, black pixels stay black to the YCoCg clamp's rounding in the
// encoded domain (a few 2^-24 where neighbours encode near 1: 2^-46 decoded), and every value
// is finite and normal.
TEST(Taa, DisplayDomainKeepsBlackAndExtremePixelsOnEveryCpuPath) {
  const float values[] = {0.0f, 0x1p-60f, 1e-30f, 0.5f, 1e30f};
  const Plane3 mixed = image([&](int x, int y, int c) { return values[(x + 2 * y + c) % 5]; });
  const Plane3 black = image([](int, int, int) { return 0.0f; });
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    for (const Plane3* in : {&black, &mixed}) {
      Taa taa;
      Plane3 out;
      for (int f = 0; f < 3; ++f) out = taa.run(shifted(0.0f), *in, settings(0.1f, TaaDomain::display));
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < out[c].size(); ++i) {
          const float v = out[c].data[i], x = (*in)[c].data[i];
          ASSERT_TRUE(std::isfinite(v)) << cpuPathName(path) << " " << i;
          EXPECT_NE(std::fpclassify(v), FP_SUBNORMAL) << cpuPathName(path) << " " << i;
          if (in == &black) {
            EXPECT_EQ(v, 0.0f) << cpuPathName(path) << " " << i;
          }
          if (x == 0.0f) {
            EXPECT_LE(v, 0x1p-46f) << cpuPathName(path) << " " << i;
          }
          if (x == 0.5f) {
            EXPECT_NEAR(v, 0.5f, 1e-6f) << cpuPathName(path) << " " << i;
          }
        }
    }
  }
}

// The transfer pair round-trips on LDR and HDR values, maps [0, inf) into [0, 1), and gives
// NaN and negative values 0.
TEST(Taa, DisplayEncodingRoundTrips) {
  for (float x : {0.0f, 1e-6f, 0.01f, 0.18f, 0.5f, 1.0f, 4.0f, 100.0f, 1e4f}) {
    const float e = tonemap::taaEncode(x);
    EXPECT_GE(e, 0.0f);
    EXPECT_LT(e, 1.0f);
    EXPECT_NEAR(e, std::sqrt(double(x) / (1.0 + x)), 1e-7);
    EXPECT_NEAR(tonemap::taaDecode(e), x, 4e-7 * (1.0 + x) * (1.0 + x)) << x;
  }
  EXPECT_EQ(tonemap::taaEncode(-1.0f), 0.0f);
  EXPECT_EQ(tonemap::taaEncode(std::nanf("")), 0.0f);
  EXPECT_EQ(tonemap::taaEncode(INFINITY), 1.0f);
  EXPECT_LE(tonemap::taaDecode(1.0f), 1.1e6f);  // clamped below the pole
}

// On an LDR image both domains do the same thing where the history is the image itself (a
// static scene), within the transfer functions' float precision: frame 0 passes through
// exactly, later frames return the image.
TEST(Taa, LinearAndDisplayAgreeOnAStaticLdrImage) {
  const Plane3 in = image([](int x, int y, int c) { return float((x * 7 + y * 13 + c * 5) % 17) / 16.0f; });
  Taa linear, display;
  for (int f = 0; f < 3; ++f) {
    const Plane3& a = linear.run(shifted(0.0f), in, settings(0.1f, TaaDomain::linear));
    const Plane3& b = display.run(shifted(0.0f), in, settings(0.1f, TaaDomain::display));
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < in[c].size(); ++i) {
        if (f == 0) { EXPECT_EQ(b[c].data[i], in[c].data[i]); }
        EXPECT_NEAR(a[c].data[i], in[c].data[i], 1e-6f);
        EXPECT_NEAR(b[c].data[i], a[c].data[i], 4e-6f) << "frame " << f;
      }
  }
}

// One pixel at 1000x the others' radiance (a small emitter), seen through a reprojection half a
// pixel off (jitter without motion vectors): the neighbour on its left fetches half of its
// history and, the emitter being in its 3x3 box, keeps it. In linear radiance the neighbour
// converges to v = a*0.5 + (1 - a)(E/2 + v/2), hundreds of times its own value; in the display
// domain the same recurrence runs on encoded values bounded by 1, so v stays below
// decode((a e(0.5) + (1 - a)/2) / (1 - (1 - a)/2)), computed here in double.
TEST(Taa, BrightPixelDoesNotDominateItsNeighboursInTheDisplayDomain) {
  const int ex = 11, ey = 8;
  const float base = 0.5f, bright = 500.0f, a = 0.1f;
  const Plane3 in = image([&](int x, int y, int) { return x == ex && y == ey ? bright : base; });
  double neighbour[2];
  for (TaaDomain d : {TaaDomain::linear, TaaDomain::display}) {
    Taa taa;
    Plane3 out;
    for (int f = 0; f < 40; ++f) out = taa.run(shifted(0.5f), in, settings(a, d));
    neighbour[int(d)] = out[1](ex - 1, ey);
    EXPECT_NEAR(out[1](ex - 3, ey), base, 1e-5f) << "pixels outside the emitter's box are untouched";
  }
  const double e0 = std::sqrt(base / (1.0 + base));
  const double bound = (a * e0 + (1 - a) / 2) / (1 - (1 - a) / 2), boundLinear = bound * bound / (1 - bound * bound);
  EXPECT_GT(neighbour[0], 100.0 * base) << "linear: the emitter's history spreads";
  EXPECT_LE(neighbour[1], boundLinear);
  EXPECT_LT(neighbour[1], 12.0 * base);
}

// A grey 0.5 frame whose diagonal neighbours are 0.9 (pixels with odd x and y): the 3x3 box
// reaches 0.9, the 5-tap cross only 0.5. A grey history of 0.8 is inside the box (kept) but
// clamped by the BMFR code's mean bounds to (0.9 + 0.5) / 2 = 0.7.
TEST(Taa, BoxCrossBoundsAreTheMeanOfTheBoxAndTheCross) {
  const float alpha = 0.25f;
  const Plane3 cur = image([](int x, int y, int) { return x % 2 && y % 2 ? 0.9f : 0.5f; });
  const Plane3 hist = image([](int, int, int) { return 0.8f; });
  for (TaaNeighbourhood shape : {TaaNeighbourhood::box3x3, TaaNeighbourhood::boxCross}) {
    Taa taa;
    Plane3 out = taa.run(shifted(0.0f), hist, settings(alpha, TaaDomain::linear, shape));
    out = taa.run(shifted(0.0f), cur, settings(alpha, TaaDomain::linear, shape));
    const float clamped = shape == TaaNeighbourhood::box3x3 ? 0.8f : 0.7f;
    for (int y = 2; y < kH - 2; y += 2)
      for (int x = 2; x < kW - 2; x += 2)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[c](x, y), alpha * 0.5f + (1 - alpha) * clamped, 1e-6f) << x << "," << y;
  }
}

// An image moving one pixel left per frame, with motion saying so: the history of every
// pixel is exactly its current value, so the output is the input. Without the motion the
// history is the neighbour's value and the output differs.
TEST(Taa, ExactMotionReproducesAMovingImage) {
  auto frame = [](int t) {
    return image([t](int x, int y, int c) { return 0.5f + 0.4f * std::sin(0.9f * (x + t) + 0.3f * y + c); });
  };
  Taa taa;
  Plane3 out;
  out = taa.run(shifted(1.0f), frame(0), settings(0.1f));
  const Plane3 cur = frame(1);
  out = taa.run(shifted(1.0f), cur, settings(0.1f));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW - 1; ++x)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[c](x, y), cur[c](x, y), 2e-6f) << x << "," << y;

  Taa still;
  out = still.run(shifted(0.0f), frame(0), settings(0.1f));
  out = still.run(shifted(0.0f), cur, settings(0.1f));
  double err = 0;
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < out[c].size(); ++i) err = std::max(err, double(std::abs(out[c].data[i] - cur[c].data[i])));
  EXPECT_GT(err, 0.05);
}

// A white history over a black frame lies outside the frame's 3x3 box ({0}): it is clamped to
// black, so nothing ghosts.
TEST(Taa, ClampRejectsHistoryOutsideTheNeighbourhood) {
  Taa taa;
  Plane3 out;
  out = taa.run(shifted(0.0f), image([](int, int, int) { return 1.0f; }), settings(0.1f));
  out = taa.run(shifted(0.0f), image([](int, int, int) { return 0.0f; }), settings(0.1f));
  for (int c = 0; c < 3; ++c)
    for (float v : out[c].data) EXPECT_EQ(v, 0.0f);
}

// Grey history 0.5 inside the box of a grey 0.4/0.6 checkerboard: not clamped, so the output
// is alpha * current + (1 - alpha) * 0.5 exactly (grey has Co = Cg = 0).
TEST(Taa, HistoryInsideTheBoxIsBlendedWithAlpha) {
  Taa taa;
  Plane3 out;
  const float alpha = 0.25f;
  out = taa.run(shifted(0.0f), image([](int, int, int) { return 0.5f; }), settings(alpha));
  const Plane3 checker = image([](int x, int y, int) { return (x + y) % 2 ? 0.6f : 0.4f; });
  out = taa.run(shifted(0.0f), checker, settings(alpha));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(out[c](x, y), alpha * checker[c](x, y) + (1 - alpha) * 0.5f, 1e-6f) << x << "," << y;
}

// taaSubpixelAlpha: the same grey history inside the checkerboard's box, fetched at subpixel
// offsets (dx, dy): the weight of the current frame is min(1, alpha + k (fx (1 - fx) + fy (1 - fy)))
// with fx, fy the offsets' fractional parts (computed here in double), alpha itself at whole-pixel
// offsets. Pixels whose fetch lies off the frame keep the current colour. Both history filters
// (a constant history is exact under either), the plain and the keyed box (two key regions, each
// wide enough to hold both checker greys), every CPU path.
TEST(Taa, SubpixelAlphaRaisesTheBlendWeightByTheFetchVariance) {
  const Plane3 grey = image([](int, int, int) { return 0.5f; });
  const Plane3 checker = image([](int x, int y, int) { return (x + y) % 2 ? 0.6f : 0.4f; });
  PixelVector<uint32_t> keys(size_t(kW) * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) keys[size_t(y) * kW + x] = x < kW / 2 ? 3u : 5u;
  const double alpha = 0.1;
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    for (TaaHistoryFilter filter : kFilters)
      for (bool keyed : {false, true})
        for (float k : {0.0f, 1.0f, 3.0f})
          for (const auto& [dx, dy] : {std::pair{0.0f, 0.0f}, {0.25f, 0.0f}, {0.5f, 0.0f}, {1.0f, 0.0f}, {0.25f, 0.5f},
                                       {0.5f, 0.5f}, {1.25f, 0.75f}}) {
            TaaSettings s = settings(float(alpha), TaaDomain::linear, TaaNeighbourhood::box3x3, filter);
            s.taaSubpixelAlpha = k;
            s.taaOwnSurface = keyed;
            Taa taa;
            taa.run(shifted(0.0f), grey, s, keyed ? &keys : nullptr);
            const Plane3& out = taa.run(test::shiftedReprojection(kW, kH, dx, dy), checker, s, keyed ? &keys : nullptr);
            auto variance = [](double d) { const double f = d - std::floor(d); return f * (1 - f); };
            const double a = std::min(1.0, alpha + k * (variance(dx) + variance(dy)));
            for (int y = 0; y < kH; ++y)
              for (int x = 0; x < kW; ++x) {
                const bool inside = x + dx < kW && y + dy < kH;
                for (int c = 0; c < 3; ++c) {
                  const double cur = checker[c](x, y);
                  const double want = inside ? a * cur + (1 - a) * 0.5 : cur;
                  ASSERT_NEAR(out[c](x, y), want, 2e-6)
                      << cpuPathName(path) << " " << name(filter) << (keyed ? " keyed" : "") << " k " << k << " offset (" << dx
                      << ", " << dy << ") at " << x << "," << y;
                }
              }
          }
  }
}

// The raised weight stays a weight wherever the reprojection puts the history: pixels whose
// fetch lies off the frame (the reprojection's kOffFrame, 1e10, infinity, NaN) keep the current
// colour with taaSubpixelAlpha 8 as with 0, on every CPU path.
TEST(Taa, SubpixelAlphaKeepsTheCurrentColourWhereThereIsNoHistory) {
  const Plane3 cur = image([](int x, int, int c) { return 0.1f * c + 0.01f * x; });
  const float far[] = {Reprojection::kOffFrame, 1e10f, -1e10f, 3e38f, INFINITY, -INFINITY, NAN};
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    for (TaaHistoryFilter filter : kFilters)
      for (TaaDomain d : {TaaDomain::linear, TaaDomain::display}) {
        TaaSettings s = settings(0.1f, d, TaaNeighbourhood::box3x3, filter);
        s.taaSubpixelAlpha = 8.0f;
        Taa taa;
        taa.run(shifted(0.0f), image([](int, int, int) { return 0.9f; }), s);
        Reprojection rp = shifted(0.0f);
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x) {
            rp.prevX(x, y) = far[size_t(x + y) % std::size(far)];
            rp.prevY(x, y) = far[size_t(x + 2 * y) % std::size(far)] * (x % 2 ? 1.0f : 0.0f) + y + 0.5f;
          }
        const Plane3& out = taa.run(rp, cur, s);
        for (int c = 0; c < 3; ++c)
          for (size_t i = 0; i < out[c].size(); ++i)
            ASSERT_NEAR(out[c].data[i], cur[c].data[i], 1e-6f) << cpuPathName(path) << " " << name(filter) << " pixel " << i;
      }
  }
}

// The same in the display domain: the blend runs on encoded values, e = sqrt(x / (1 + x)),
// and the output is their decode, computed here in double.
TEST(Taa, DisplayDomainBlendsEncodedValues) {
  Taa taa;
  Plane3 out;
  const float alpha = 0.25f;
  auto e = [](double x) { return std::sqrt(x / (1.0 + x)); };
  out = taa.run(shifted(0.0f), image([](int, int, int) { return 3.0f; }), settings(alpha, TaaDomain::display));
  const Plane3 checker = image([](int x, int y, int) { return (x + y) % 2 ? 8.0f : 1.0f; });
  out = taa.run(shifted(0.0f), checker, settings(alpha, TaaDomain::display));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double b = alpha * e(checker[0](x, y)) + (1 - alpha) * e(3.0), want = b * b / (1 - b * b);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[c](x, y), want, 2e-6 * want * (1 + want)) << x << "," << y;
    }
}

// What the display domain costs (docs/methods/taa.md, "The domain"): residual noise averaged
// over time decodes darker than its mean radiance. A grey frame whose pixels alternate between
// 0.2 and 1.8 in a checkerboard that flips every frame, under a still camera: every 3x3 box
// spans [0.2, 1.8], so nothing is clamped and the blend is a running average. In linear
// radiance the mean of two consecutive outputs converges to the mean radiance 1. In the display
// domain the running average of encoded values e(x) = sqrt(x / (1 + x)) settles into the cycle
// h_a = (a e_a + a (1 - a) e_b) / (1 - (1 - a)^2) and its twin: their decodes' mean (computed
// here in double) is 0.578, 42 % darker (Jensen: the encoding is concave). The same concavity
// is what keeps a bright pixel from spreading (BrightPixelDoesNotDominateItsNeighboursInTheDisplayDomain).
TEST(Taa, DisplayDomainDarkensTemporalNoiseByTheEncodingsConcavity) {
  const float lo = 0.2f, hi = 1.8f;
  auto frame = [&](int t) { return image([&](int x, int y, int) { return (x + y + t) % 2 ? hi : lo; }); };
  const Plane3 f0 = frame(0), f1 = frame(1);
  auto e = [](double x) { return std::sqrt(x / (1.0 + x)); };
  const double al = 0.1, ha = (al * e(lo) + al * (1 - al) * e(hi)) / (1 - (1 - al) * (1 - al)),
               hb = (al * e(hi) + al * (1 - al) * e(lo)) / (1 - (1 - al) * (1 - al));
  auto decode = [](double y) { return y * y / (1 - y * y); };
  const double displayMean = 0.5 * (decode(ha) + decode(hb));
  for (TaaDomain d : {TaaDomain::linear, TaaDomain::display}) {
    Taa taa;
    Plane3 a, b;
    for (int f = 0; f < 200; ++f) {
      a = b;
      b = taa.run(shifted(0.0f), f % 2 ? f1 : f0, settings(0.1f, d));
    }
    const double want = d == TaaDomain::display ? displayMean : 1.0;
    for (int y = 1; y < kH - 1; ++y)
      for (int x = 1; x < kW - 1; ++x) ASSERT_NEAR(0.5 * (a[1](x, y) + b[1](x, y)), want, 1e-5) << int(d) << " " << x << "," << y;
  }
  EXPECT_LT(displayMean, 0.9);  // the test tells the domains apart
}

// taaHistoryRejection: where the reprojection's record accepted no history tap (kind None: a
// disocclusion), the pixel keeps the current frame, whatever its reprojected position says;
// elsewhere nothing changes. A white history under a 0/1 checkerboard, still camera: every
// 3x3 box spans [0, 1], so the white history is kept and blended (a c + (1 - a)) except at the
// rejected pixels (every fifth, so some 8-pixel groups of the avx2 path hold one), which
// return c exactly with the setting and the blend without it. On every CPU path, both filters.
TEST(Taa, HistoryRejectionKeepsTheCurrentFrameWhereTheReprojectionFoundNoHistory) {
  const float alpha = 0.1f;
  const Plane3 white = image([](int, int, int) { return 1.0f; });
  const Plane3 checker = image([](int x, int y, int) { return (x + y) % 2 ? 1.0f : 0.0f; });
  Reprojection rp = shifted(0.0f);
  auto none = [](int x, int y) { return (x + 3 * y) % 5 == 0; };
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (none(x, y)) rp.kind[size_t(y) * kW + x] = Reprojection::None;
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    for (TaaHistoryFilter filter : kFilters)
      for (bool rejection : {false, true}) {
        TaaSettings s = settings(alpha, TaaDomain::linear, TaaNeighbourhood::box3x3, filter);
        s.taaHistoryRejection = rejection;
        Taa taa;
        Plane3 out = taa.run(rp, white, s);
        out = taa.run(rp, checker, s);
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x) {
            const float c = checker[0](x, y), want = rejection && none(x, y) ? c : alpha * c + (1 - alpha);
            for (int k = 0; k < 3; ++k)
              ASSERT_NEAR(out[k](x, y), want, 1e-6f) << cpuPathName(path) << " " << name(filter) << " " << rejection << " " << x << "," << y;
          }
      }
  }
}

// A pixel whose reprojected centre is outside the previous frame keeps its current colour.
TEST(Taa, PixelsWithoutHistoryKeepTheCurrentColour) {
  for (TaaHistoryFilter filter : kFilters) {
    Taa taa;
    Plane3 out;
    const TaaSettings lin = settings(0.1f, TaaDomain::linear, TaaNeighbourhood::box3x3, filter);
    out = taa.run(shifted(0.0f), image([](int, int, int) { return 0.9f; }), lin);
    const Plane3 cur = image([](int x, int, int c) { return 0.1f * c + 0.01f * x; });
    out = taa.run(shifted(-float(kW) - 2.0f), cur, lin);
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < out[c].size(); ++i) EXPECT_NEAR(out[c].data[i], cur[c].data[i], 1e-6f) << name(filter);
    Taa display;
    const TaaSettings disp = settings(0.1f, TaaDomain::display, TaaNeighbourhood::box3x3, filter);
    out = display.run(shifted(0.0f), image([](int, int, int) { return 0.9f; }), disp);
    out = display.run(shifted(-float(kW) - 2.0f), cur, disp);
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < out[c].size(); ++i) EXPECT_NEAR(out[c].data[i], cur[c].data[i], 1e-6f) << name(filter);
  }
}

// The vector paths read a group of pixels' history taps with vector loads where the footprints
// are consecutive and with gathers otherwise (bilinear, Bilinear8); Catmull-Rom (8 or 16
// pixels) reads them as permutations of two-vector windows of one or two rows where they start
// within a few columns and on two rows at most (a step in the motion; positions that round to
// either side of a texel centre line, as under a static or panning camera). Four motion fields
// make each layout the common case (classified here from the positions, groups of eight); on
// every CPU path, with either history filter, the TAA output equals the sse2 path's (scalar
// fetches) to float rounding. A wrong lane in a window's permutation moves a value by ~0.1 here.
TEST(Taa, HistoryTapsOfEveryGroupLayoutEqualTheScalarFetch) {
  const int w = 101, h = 23;
  enum Field { Uniform, Stepped, Straddling, Scattered };
  for (const Field field : {Uniform, Stepped, Straddling, Scattered}) {
    SCOPED_TRACE("motion field " + std::to_string(int(field)));
    uint32_t state = 7919u * (unsigned(field) + 1);
    auto rnd = [&] {
      state = state * 1664525u + 1013904223u;
      return float(state >> 8) * 0x1p-24f;
    };
    Reprojection rp;
    rp.resize(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float dx = 2.3f, dy = -0.6f;                      // Uniform: consecutive groups
        if (field == Stepped) dx += 0.09f * float(x);      // a one-column step every ~11 pixels
        if (field == Straddling) dx = 1.0f + 1e-4f * (rnd() - 0.5f), dy = -1.0f + 1e-4f * (rnd() - 0.5f);
        if (field == Scattered) dx = 16.0f * rnd() - 8.0f, dy = 16.0f * rnd() - 8.0f;
        rp.prevX(x, y) = float(x) + 0.5f + dx;
        rp.prevY(x, y) = float(y) + 0.5f + dy;
      }
    acceptAll(rp);
    // The layout of each group of eight bilinear footprints inside the frame.
    size_t layouts[4] = {};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x + 8 <= w; x += 8) {
        int fx[8], fy[8];
        bool inside = true;
        for (int k = 0; k < 8; ++k) {
          fx[k] = int(std::floor(rp.prevX(x + k, y) - 0.5f)), fy[k] = int(std::floor(rp.prevY(x + k, y) - 0.5f));
          inside = inside && fx[k] >= 0 && fy[k] >= 0 && fx[k] < w - 1 && fy[k] < h - 1;
        }
        if (!inside) continue;
        bool consecutive = true;
        for (int k = 0; k < 8; ++k) consecutive = consecutive && fy[k] == fy[0] && fx[k] == fx[0] + k;
        const int columns = *std::max_element(fx, fx + 8) - *std::min_element(fx, fx + 8);
        const int rows = *std::max_element(fy, fy + 8) - *std::min_element(fy, fy + 8);
        ++layouts[consecutive ? Uniform : columns <= 14 && rows == 0 ? Stepped : columns <= 14 && rows == 1 ? Straddling : Scattered];
      }
    const size_t groups = layouts[0] + layouts[1] + layouts[2] + layouts[3];
    ASSERT_GT(layouts[field], groups / 2) << layouts[0] << " " << layouts[1] << " " << layouts[2] << " " << layouts[3];
    const Plane3 history = test::imageOf(w, h, [&](int, int, int) { return 0.2f + 0.6f * rnd(); });
    const Plane3 current = test::imageOf(w, h, [&](int, int, int) { return rnd() < 0.5f ? 0.0f : 1.0f; });
    for (TaaHistoryFilter filter : kFilters) {
      const TaaSettings s = settings(0.3f, TaaDomain::linear, TaaNeighbourhood::box3x3, filter);
      auto run = [&] {
        Taa taa;
        taa.resize(w, h);
        taa.run(rp, history, s);  // no history yet: stores `history`
        return taa.run(rp, current, s);
      };
      Plane3 ref;
      {
        test::ScopedCpuPath scalar(CpuPath::Sse2);
        ref = run();
      }
      for (CpuPath path : test::supportedCpuPaths()) {
        test::ScopedCpuPath force(path);
        const Plane3 out = run();
        for (int c = 0; c < 3; ++c)
          for (size_t i = 0; i < out[c].size(); ++i)
            ASSERT_NEAR(out[c].data[i], ref[c].data[i], 2e-6f) << cpuPathName(path) << " " << name(filter) << " pixel " << i;
      }
    }
  }
}

// Catmull-Rom (Keys' a = -1/2 cubic) reproduces quadratics, bilinear does not: a colour image
// q(x, y) quadratic in x and y, moved by a sub-pixel (0.3, 0.6) per frame with motion saying so.
// Where the 4x4 footprint lies inside the frame, the Catmull-Rom history is the current frame
// itself, so the output is the input; the bilinear history is off by the interpolation error
// of the quadratic terms, c_x t(1 - t) + c_y s(1 - s) (t, s the fractions), which lies inside
// the 3x3 box of this monotone image and enters the output with weight 1 - alpha. Where the
// reprojection rejected a tap, Catmull-Rom falls back to (plain) bilinear. On every CPU path.
TEST(Taa, CatmullRomReproducesAQuadraticAndFallsBackToBilinearOnRejectedTaps) {
  const double sx = 0.3, sy = 0.6, cx = 0.002, cy = 0.003, alpha = 0.25;
  auto q = [&](double x, double y, int c) { return (1.0 + 0.2 * c) * (0.1 + 0.02 * x + 0.03 * y + cx * x * x + cy * y * y); };
  const Plane3 prev = image([&](int x, int y, int c) { return float(q(x, y, c)); });
  const Plane3 cur = image([&](int x, int y, int c) { return float(q(x + sx, y + sy, c)); });
  Reprojection rp = shifted(float(sx));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) rp.prevY(x, y) += float(sy);
  acceptAll(rp);
  // On every fourth row, every third pixel loses its history taps' consistency (a dropped
  // tap, or no history record at all): there Catmull-Rom falls back to bilinear. The other
  // rows take the eight-pixel path on avx2 and avx512 (x = 8..15).
  auto rejected = [](int x, int y) { return y % 4 == 3 && (x + y) % 3 == 0; };
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (rejected(x, y)) {
        const size_t i = size_t(y) * kW + x;
        if (x % 2) rp.kind[i] = Reprojection::None;
        else rp.weights[i] = {0.0f, 0.4f, 0.3f, 0.3f};  // the top-left tap dropped
      }
  const double bilinearError = cx * sx * (1 - sx) + cy * sy * (1 - sy);
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    for (TaaHistoryFilter filter : kFilters) {
      // The records without any tap (kind None) stand for a history that bilinear still
      // fetches: taaHistoryRejection (which would keep the current frame there, tested in
      // HistoryRejectionKeepsTheCurrentFrameWhereTheReprojectionFoundNoHistory) is off here.
      TaaSettings s = settings(float(alpha), TaaDomain::linear, TaaNeighbourhood::box3x3, filter);
      s.taaHistoryRejection = false;
      Taa taa;
      Plane3 out = taa.run(rp, prev, s);
      out = taa.run(rp, cur, s);
      for (int y = 1; y < kH - 3; ++y)
        for (int x = 1; x < kW - 3; ++x)
          for (int c = 0; c < 3; ++c) {
            const double want = filter == TaaHistoryFilter::catmullRom && !rejected(x, y)
                                    ? cur[c](x, y)
                                    : cur[c](x, y) + (1 - alpha) * (1.0 + 0.2 * c) * bilinearError;
            ASSERT_NEAR(out[c](x, y), want, 2e-6) << cpuPathName(path) << " " << name(filter) << " " << x << "," << y;
          }
    }
  }
}

// Which filter takes a pixel's history does not turn on a texel the bilinear footprint weighs
// by a rounding error (kTaaNegligibleTap): history on the pixel centre rows (prevY exactly on
// them), and the same rows 1e-5 px lower with the row below rejected by the reprojection (a
// surface edge under each row, as other scene units or camera conventions round it), both take
// the Catmull-Rom history, which reproduces the image's quadratic x profile; the bilinear one
// would be off by (1 - alpha) c t (1 - t) = 1.6e-3 here. On every CPU path.
TEST(Taa, CatmullRomIgnoresARejectedTexelOfNegligibleWeight) {
  const double sx = 0.3, c2 = 0.01, alpha = 0.25;
  auto q = [&](double x, double y, int c) { return (1.0 + 0.2 * c) * (0.1 + 0.02 * x + c2 * x * x + 0.005 * y); };
  const Plane3 prev = image([&](int x, int y, int c) { return float(q(x, y, c)); });
  const Plane3 cur = image([&](int x, int y, int c) { return float(q(x + sx, y, c)); });
  for (float below : {0.0f, 1e-5f}) {
    Reprojection rp = shifted(float(sx));
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        rp.prevY(x, y) += below;
        setBilinear(rp, size_t(y) * kW + x, rp.prevX(x, y), rp.prevY(x, y), [&](int, int ty) { return ty == y; });
      }
    for (CpuPath path : test::supportedCpuPaths()) {
      test::ScopedCpuPath force(path);
      TaaSettings s = catmullRom(float(alpha));
      Taa taa;
      Plane3 out = taa.run(rp, prev, s);
      out = taa.run(rp, cur, s);
      for (int y = 1; y < kH - 3; ++y)
        for (int x = 1; x < kW - 3; ++x)
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(out[c](x, y), cur[c](x, y), 2e-5) << cpuPathName(path) << " below " << below << " at " << x << "," << y;
    }
  }
}

// Catmull-Rom's negative lobes overshoot at an edge; the neighbourhood clamp contains them. A
// 0/1 step at x = 10 (history and frame), the history fetched half a pixel to the right: the
// cubic gives -1/16 at x = 8 (taps 7..10 = 0 0 0 1) and 17/16 at x = 10 (0 1 1 1), outside the
// 3x3 boxes [0, 0] and [0, 1]; clamped, the outputs are 0 and 1, and at x = 9 (taps 0 0 1 1:
// 1/2, inside) a * 0 + (1 - a) / 2.
TEST(Taa, CatmullRomOvershootIsClampedToTheNeighbourhood) {
  const float alpha = 0.1f;
  const Plane3 step = image([](int x, int, int) { return x >= 10 ? 1.0f : 0.0f; });
  for (TaaDomain d : {TaaDomain::linear, TaaDomain::display}) {
    Taa taa;
    Plane3 out = taa.run(shifted(0.5f), step, catmullRom(alpha, d));
    out = taa.run(shifted(0.5f), step, catmullRom(alpha, d));
    for (int y = 0; y < kH; ++y)
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(out[c](8, y), 0.0f) << int(d);
        EXPECT_NEAR(out[c](10, y), 1.0f, 1e-6f) << int(d);
        EXPECT_NEAR(out[c](11, y), 1.0f, 1e-6f) << int(d);
        if (d == TaaDomain::linear) EXPECT_NEAR(out[c](9, y), (1 - alpha) * 0.5f, 1e-6f);
        else {  // the blend of encoded values: e(0) = 0, e(1) = sqrt(1/2)
          const double b = (1 - alpha) * 0.5 * std::sqrt(0.5);
          EXPECT_NEAR(out[c](9, y), b * b / (1 - b * b), 1e-6);
        }
      }
  }
}

// The blur of the history filter under sub-pixel motion (issue 12): a noise-free sinusoid of
// period P pixels (amplitude 0.3 on 0.5, phase shifted per channel) panning left at v px/frame,
// each frame sampled exactly at the pixel centres, with exact motion. A perfect history filter
// would make the output the frame itself. Resampling multiplies the history's sinusoid by the
// filter's response H at the fraction t = v (t = 1/2: bilinear cos(w/2), Catmull-Rom
// 9/8 cos(w/2) - 1/8 cos(3w/2), w = 2 pi / P) every frame, and the blend
// out = a c + (1 - a) H out' compounds it to a / (1 - (1 - a) H) of the true amplitude where the
// clamp does not bind (bilinear at P = 8: 0.60, Catmull-Rom 0.93). After 48 frames the
// Catmull-Rom output's error is below bilinear's at every period and less than half of it from
// P = 6 on, on every CPU path and in both domains (the relative RMSEs are recorded as test
// properties, docs/methods/taa.md). At integer speeds both are exact
// (Taa.ExactMotionReproducesAMovingImage).
TEST(Taa, CatmullRomBlursLessThanBilinearUnderSubPixelMotion) {
  constexpr int w = 96, h = 16, frames = 48;
  for (double v : {0.25, 0.5})
    for (double period : {3.0, 4.0, 6.0, 8.0, 16.0}) {
      auto frame = [&](double offset) {
        Plane3 p;
        resize(p, w, h);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) p[c](x, y) = float(0.5 + 0.3 * std::sin(2 * M_PI * (x + offset) / period + 0.5 * c));
        return p;
      };
      Reprojection rp;
      rp.resize(w, h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) { rp.prevX(x, y) = float(x + 0.5 + v); rp.prevY(x, y) = y + 0.5f; }
      acceptAll(rp);
      std::vector<Plane3> seq;
      for (int f = 0; f < frames; ++f) seq.push_back(frame(v * f));
      for (CpuPath path : test::supportedCpuPaths()) {
        test::ScopedCpuPath force(path);
        for (TaaDomain d : {TaaDomain::linear, TaaDomain::display}) {
          double rel[2];
          for (TaaHistoryFilter filter : kFilters) {
            Taa taa;
            Plane3 out;
            for (int f = 0; f < frames; ++f) out = taa.run(rp, seq[size_t(f)], settings(0.1f, d, TaaNeighbourhood::box3x3, filter));
            double se = 0;
            int n = 0;
            for (int y = 0; y < h; ++y)
              for (int x = 4; x < w - 8; ++x)  // away from the right border, where content enters
                for (int c = 0; c < 3; ++c, ++n) se += std::pow(double(out[c](x, y)) - seq.back()[c](x, y), 2);
            rel[int(filter)] = std::sqrt(se / n) / (0.3 / std::sqrt(2.0));  // RMSE / RMS of the sinusoid
            char key[96];
            std::snprintf(key, sizeof key, "relrmse_v%.2f_P%g_%s_%s_%s", v, period, name(filter),
                          d == TaaDomain::linear ? "linear" : "display", cpuPathName(path));
            RecordProperty(key, std::to_string(rel[int(filter)]));
          }
          const std::string what = "v " + std::to_string(v) + " P " + std::to_string(period) + " " + cpuPathName(path) +
                                   (d == TaaDomain::linear ? " linear" : " display");
          EXPECT_LT(rel[1], rel[0]) << what;
          if (period >= 6) { EXPECT_LT(rel[1], 0.5 * rel[0]) << what; }
        }
      }
    }
}

// A frame run with an output view (RgbExport: each row handed over as it is blended, as the
// methods' last pass writes the output) writes exactly what exporting the plain run's result
// writes, and keeps the same history: both domains and history filters, with and without
// surface keys and emission, every output layout, the first frame (no history) and later
// ones, the rows in one run() or in bands as BMFR runs them, on every CPU path.
TEST(Taa, RowsHandedToAnOutputViewEqualTheExportOfTheResult) {
  constexpr int w = 53, h = 21;  // several 16-pixel groups and a tail
  std::vector<Plane> emission(3);
  for (int c = 0; c < 3; ++c) {
    emission[size_t(c)].resize(w, h);
    for (int i = 0; i < w * h; ++i) emission[size_t(c)].data[size_t(i)] = float((i * 7 + c * 3) % 11) / 4.0f;
  }
  PixelVector<uint32_t> keys(size_t(w) * h);
  for (int i = 0; i < w * h; ++i) keys[size_t(i)] = (i % w) + (i / w) / 3 < 30 ? 1u : 2u;
  auto frame = [&](int f) {
    return test::imageOf(w, h, [f](int x, int y, int c) {
      return 0.02f + float(((x + 2 * f) * 37 + y * 11 + c * 5) % 97) / 20.0f;
    });
  };
  struct Layout { Format format; int extraChannels; };
  const Layout layouts[] = {{Format::Float3, 0}, {Format::Float4, 0}, {Format::Float4, 1}, {Format::Half3, 0}, {Format::Half4, 1}};
  for (CpuPath path : test::supportedCpuPaths()) {
    test::ScopedCpuPath force(path);
    for (TaaDomain d : {TaaDomain::linear, TaaDomain::display})
      for (TaaHistoryFilter filter : kFilters)
        for (bool keyed : {false, true})
          for (bool withEmission : {false, true})
            for (const Layout& layout : layouts)
              for (bool banded : {false, true}) {
                TaaSettings s = settings(0.1f, d, TaaNeighbourhood::box3x3, filter);
                s.taaSubpixelAlpha = 2.0f;
                s.taaOwnSurface = keyed;
                const std::vector<Plane>* e = withEmission ? &emission : nullptr;
                const size_t channelBytes = isHalf(layout.format) ? 2 : 4;
                const size_t pixelBytes = (size_t(channelCount(layout.format)) + layout.extraChannels) * channelBytes;
                Taa plain, handed;
                for (int f = 0; f < 3; ++f) {
                  const Plane3 color = frame(f);
                  const Reprojection rp = test::shiftedReprojection(w, h, 0.3f + 0.2f * f, -0.45f);
                  std::vector<unsigned char> want(pixelBytes * w * h, 0xab), got(want.size(), 0xab);
                  const ImageView wantView{want.data(), w, h, layout.format, pixelBytes};
                  const ImageView gotView{got.data(), w, h, layout.format, pixelBytes};
                  exportRgb(plain.run(rp, color, s, &keys), e, wantView);
                  const RgbExport rows(gotView, w, h, e);
                  if (banded) {
                    handed.begin(w, h, s, &keys, &rows);
                    for (int y = 0; y < h; y += 5) handed.runRows(rp, color, y, std::min(y + 5, h));
                  } else {
                    handed.run(rp, color, s, &keys, &rows);
                  }
                  ASSERT_EQ(std::memcmp(got.data(), want.data(), got.size()), 0)
                      << cpuPathName(path) << " domain " << int(d) << " " << name(filter) << " keys " << keyed << " emission "
                      << withEmission << " format " << int(layout.format) << " banded " << banded << " frame " << f;
                }
              }
  }
}

}  // namespace
}  // namespace rtd
