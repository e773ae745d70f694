// Metrics against independently known values (see each test for where the value comes from).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "rtd/eval/metrics.h"

using namespace rtd;
using namespace rtd::eval;

namespace {
Image pattern(int w, int h, int c, uint32_t seed) {
  Image img(w, h, c);
  uint32_t s = seed;
  for (float& v : img.pixels) {
    s = s * 1664525u + 1013904223u;
    v = float(s >> 8) / float(1u << 24);
  }
  return img;
}

// The fixed pairs of tools/eval/ssim_psnr_reference.py (integer formulas, exact in both).
void pairA(Image& a, Image& b) {
  a = Image(32, 24, 3);
  b = Image(32, 24, 3);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c) {
        const int base = (x * 7 + y * 13 + c * 5 + (x * y) % 11) % 256;
        const int hsh = int((uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^ uint32_t(c) * 83492791u) % 41u) - 20;
        a.at(x, y, c) = float(base / 255.0);
        b.at(x, y, c) = float(std::clamp(base + hsh, 0, 255) / 255.0);
      }
}
void pairB(Image& a, Image& b) {
  a = Image(17, 13, 1);
  b = Image(17, 13, 1);
  for (int y = 0; y < 13; ++y)
    for (int x = 0; x < 17; ++x) {
      a.at(x, y) = float(((x * x + 3 * y) % 29) / 28.0);
      b.at(x, y) = float(((x + y * y) % 31) / 30.0);
    }
}
void pairC(Image& a, Image& b) {
  a = Image(40, 36, 3);
  b = Image(40, 36, 3);
  for (int y = 0; y < 36; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 3; ++c) {
        a.at(x, y, c) = float(((x * 3 + y * 2 + c * 40) % 200) / 255.0);
        b.at(x, y, c) = float(((x * 3 + y * 2 + c * 40 + 6) % 200) * 0.8 / 255.0);
      }
}
}  // namespace

TEST(Metrics, IdenticalImages) {
  const Image a = pattern(37, 29, 3, 7);
  EXPECT_TRUE(std::isinf(psnr(a, a)));
  EXPECT_GT(psnr(a, a), 0);
  EXPECT_NEAR(ssim(a, a), 1.0, 1e-12);
  EXPECT_EQ(relMse(a, a), 0.0);
  EXPECT_EQ(rmse(a, a), 0.0);
  Image map;
  EXPECT_EQ(flip(a, a, {}, &map), 0.0);
  for (float v : map.pixels) EXPECT_EQ(v, 0.0f);
}

TEST(Metrics, HandComputedPsnrRmseRelMse) {
  // 2x2 RGB, one of 12 values differs by 0.1: MSE = 0.01 / 12, PSNR = 10 log10(1200).
  Image ref(2, 2, 3, 1.0f), test = ref;
  test.at(1, 0, 2) = 1.1f;
  EXPECT_NEAR(psnr(test, ref), 10.0 * std::log10(1200.0), 1e-4);
  EXPECT_NEAR(rmse(test, ref), std::sqrt(0.01 / 12.0), 1e-6);
  // relMSE: (0.1^2 / (1^2 + 0.01)) / 12.
  EXPECT_NEAR(relMse(test, ref), 0.01 / 1.01 / 12.0, 1e-7);
  // relMSE is scale-invariant up to epsilon: a dark reference weighs errors more.
  Image dark(2, 2, 3, 0.1f), darkTest = dark;
  darkTest.at(1, 0, 2) = 0.2f;
  EXPECT_NEAR(relMse(darkTest, dark), 0.01 / (0.01 + 0.01) / 12.0, 1e-7);
}

TEST(Metrics, SsimOfConstantImagesIsTheLuminanceTerm) {
  // Constant images: variances and covariance are 0, so SSIM = (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1)
  // with C1 = (0.01)^2 (Wang et al. 2004, eq. 13).
  const Image a(20, 16, 1, 0.5f), b(20, 16, 1, 0.25f);
  const double c1 = 1e-4;
  EXPECT_NEAR(ssim(a, b), (2 * 0.5 * 0.25 + c1) / (0.25 + 0.0625 + c1), 1e-9);
}

TEST(Metrics, PsnrAndSsimMatchScikitImage) {
  // Expected values from scikit-image 0.19.3 (Debian bookworm python3-skimage, numpy 1.24.2):
  //   /usr/bin/python3 tools/eval/ssim_psnr_reference.py
  // peak_signal_noise_ratio(a, b, data_range=1) and structural_similarity(a, b,
  // gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=1[, channel_axis=2]).
  Image a, b;
  pairA(a, b);
  EXPECT_NEAR(psnr(b, a), 26.9021625629, 1e-4);
  EXPECT_NEAR(ssim(b, a), 0.9385861323, 1e-4);
  pairB(a, b);
  EXPECT_NEAR(psnr(b, a), 7.5180045118, 1e-4);
  EXPECT_NEAR(ssim(b, a), -0.0131543765, 1e-4);
  pairC(a, b);
  EXPECT_NEAR(psnr(b, a), 16.9749622690, 1e-4);
  EXPECT_NEAR(ssim(b, a), 0.8555323473, 1e-4);
}

TEST(Metrics, MismatchedSizesThrow) {
  EXPECT_THROW(psnr(Image(4, 4, 3), Image(4, 5, 3)), rtd::Error);
  EXPECT_THROW(ssim(Image(4, 4, 3), Image(5, 4, 3)), rtd::Error);
  EXPECT_THROW(flip(Image(4, 4, 3), Image(4, 4, 1)), rtd::Error);
}

TEST(Metrics, ToneMapIsMonotoneAndEncodesSrgb) {
  Image lin(5, 1, 3);
  const float v[5] = {0.0f, 0.001f, 0.18f, 1.0f, 100.0f};
  for (int x = 0; x < 5; ++x)
    for (int c = 0; c < 3; ++c) lin.at(x, 0, c) = v[x];
  ToneMapSettings clamp{ToneMapSettings::Operator::Clamp, 0.0f};
  const Image t = toneMap(lin, clamp);
  EXPECT_EQ(t.at(0, 0), 0.0f);
  EXPECT_NEAR(t.at(1, 0), 12.92 * 0.001, 1e-6);                            // linear toe of the sRGB curve
  EXPECT_NEAR(t.at(2, 0), 1.055 * std::pow(0.18, 1 / 2.4) - 0.055, 1e-6);  // IEC 61966-2-1
  EXPECT_NEAR(t.at(3, 0), 1.0f, 1e-6);
  EXPECT_NEAR(t.at(4, 0), 1.0f, 1e-6);
  const Image aces = toneMap(lin);
  for (int x = 1; x < 5; ++x) EXPECT_GT(aces.at(x, 0), aces.at(x - 1, 0));
  EXPECT_LE(aces.at(4, 0), 1.0f);
}

// ---- FLIP against the paper's definitions (Andersson et al. 2020) ----

TEST(Flip, DefaultViewingConditions) {
  // 0.7 m from a 0.7 m wide 3840-pixel monitor: 3840 * pi / 180 = 67.02 pixels per degree.
  EXPECT_NEAR(FlipSettings{}.pixelsPerDegree(), 67.0206, 1e-3);
  // Feature detector: std. dev. 0.5 * 0.082 deg -> 2.748 pixels.
  EXPECT_NEAR(flipdetail::featureSigma(67.0206), 0.5 * 0.082 * 67.0206, 1e-9);
}

TEST(Flip, ColourSpaces) {
  // Reference white (linear RGB 1,1,1) is L* = 100, a* = b* = 0, and Yy = 100, Cx = Cz = 0.
  const float white[3] = {1, 1, 1};
  float lab[3], ycc[3], back[3];
  flipdetail::linearRgbToLab(white, lab);
  EXPECT_NEAR(lab[0], 100.0, 1e-3);
  EXPECT_NEAR(lab[1], 0.0, 1e-3);
  EXPECT_NEAR(lab[2], 0.0, 1e-3);
  flipdetail::linearRgbToYCxCz(white, ycc);
  EXPECT_NEAR(ycc[0], 100.0, 1e-3);
  EXPECT_NEAR(ycc[1], 0.0, 1e-3);
  // sRGB primaries in CIELAB (D65), published values (e.g. Lindbloom's calculator):
  // green (0,1,0) -> L 87.7347, a -86.1827, b 83.1793; blue (0,0,1) -> 32.3026, 79.1967, -107.8637.
  const float green[3] = {0, 1, 0}, blue[3] = {0, 0, 1};
  flipdetail::linearRgbToLab(green, lab);
  EXPECT_NEAR(lab[0], 87.7347, 0.01);
  EXPECT_NEAR(lab[1], -86.1827, 0.02);
  EXPECT_NEAR(lab[2], 83.1793, 0.02);
  flipdetail::linearRgbToLab(blue, lab);
  EXPECT_NEAR(lab[0], 32.3026, 0.01);
  EXPECT_NEAR(lab[1], 79.1967, 0.02);
  EXPECT_NEAR(lab[2], -107.8637, 0.02);
  // YyCxCz is linear in XYZ: the inverse round-trips.
  const float rgb[3] = {0.2f, 0.7f, 0.4f};
  flipdetail::linearRgbToYCxCz(rgb, ycc);
  flipdetail::ycxczToLinearRgb(ycc, back);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], rgb[c], 1e-5);
}

TEST(Flip, HuntHyabAndCompression) {
  float p[3] = {50, 10, 10}, q[3] = {40, 13, 14};
  // HyAB: |dL| + Euclidean distance in (a, b): 10 + 5.
  EXPECT_NEAR(flipdetail::hyab(p, q), 15.0, 1e-9);
  flipdetail::hunt(p);  // a, b scaled by 0.01 L
  EXPECT_NEAR(p[1], 5.0, 1e-6);
  EXPECT_NEAR(p[2], 5.0, 1e-6);
  // c_max from the Lab values of green and blue above, Hunt-adjusted, HyAB.
  const double gL = 87.7347, ga = -86.1827 * 0.877347, gb = 83.1793 * 0.877347;
  const double bL = 32.3026, ba = 79.1967 * 0.323026, bb = -107.8637 * 0.323026;
  const double cmax = std::abs(gL - bL) + std::hypot(ga - ba, gb - bb);
  EXPECT_NEAR(flipdetail::maxColorDistance(), cmax, 0.05);
  // Compression with q_c = 0.7, p_c = 0.4, p_t = 0.95.
  const double cm = std::pow(cmax, 0.7);
  EXPECT_NEAR(flipdetail::compressColorError(0.0), 0.0, 1e-12);
  EXPECT_NEAR(flipdetail::compressColorError(std::pow(0.4 * cm, 1 / 0.7)), 0.95, 1e-3);
  EXPECT_NEAR(flipdetail::compressColorError(cmax), 1.0, 1e-3);
  const double e = std::pow(10.0, 0.7);
  EXPECT_NEAR(flipdetail::compressColorError(10.0), e * 0.95 / (0.4 * cm), 1e-3);
}

TEST(Flip, CsfKernels) {
  // Radius: 3 std. devs of the widest Gaussian (b = 0.04): ceil(3 sqrt(0.04 / (2 pi^2)) * 67.02) = 10.
  const double ppd = FlipSettings{}.pixelsPerDegree();
  for (int ch = 0; ch < 3; ++ch) {
    int r = 0;
    const auto k = flipdetail::csfKernel(ch, ppd, &r);
    EXPECT_EQ(r, 10);
    double sum = 0;
    for (float v : k) sum += v;
    EXPECT_NEAR(sum, 1.0, 1e-5);
    // The chromatic (blue-yellow) filter is wider than the achromatic one: less weight at the centre.
    if (ch == 2) {
      const auto a = flipdetail::csfKernel(0, ppd, &r);
      EXPECT_LT(k[k.size() / 2], a[a.size() / 2]);
    }
  }
}

TEST(Flip, UniformImagesGiveTheColourTermOnly) {
  // Uniform images: the CSF filters and feature detectors change nothing (normalized kernels,
  // zero derivatives), so every pixel's error is the compressed HyAB distance of the
  // Hunt-adjusted colours; for black vs white: L 0 vs 100, a = b = 0 -> HyAB 100.
  const Image black(24, 20, 3, 0.0f), white(24, 20, 3, 1.0f);
  Image map;
  const double cmax = std::pow(flipdetail::maxColorDistance(), 0.7), e = std::pow(100.0, 0.7);
  const double expected = e < 0.4 * cmax ? e * 0.95 / (0.4 * cmax) : 0.95 + (e - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
  EXPECT_NEAR(flip(black, white, {}, &map), expected, 1e-4);
  for (float v : map.pixels) EXPECT_NEAR(v, expected, 1e-4);
}

TEST(Flip, EdgesRaiseTheErrorLocally) {
  // A thin dark line missing from the test image: error is concentrated around the line and
  // larger than the colour term alone would give there (feature term, Sec. 4.2-4.3).
  Image ref(64, 32, 3, 0.5f), test = ref;
  for (int y = 0; y < 32; ++y)
    for (int c = 0; c < 3; ++c) ref.at(32, y, c) = 0.3f;
  Image map;
  flip(test, ref, {}, &map);
  EXPECT_GT(map.at(32, 16), 0.2f);
  EXPECT_EQ(map.at(2, 16), 0.0f);
  EXPECT_GT(map.at(32, 16), map.at(28, 16));
}

// ---------------------------------------------------------------------------------------------
// HDR-FLIP (Andersson et al. 2021): the sub-steps against hand-computed values, then its
// behaviour (identical images 0, a noisier image worse, highlights the tone map hides).

TEST(HdrFlip, ToneCurveAndItsInverse) {
  // FLIP's ACES curve at x = 1: (0.36*2.51 + 0.6*0.03) / (0.36*2.43 + 0.6*0.59 + 0.14)
  // = 0.9216 / 1.3688 (by hand).
  EXPECT_NEAR(flipdetail::hdrToneMap(1.0f), 0.9216 / 1.3688, 1e-6);
  EXPECT_EQ(flipdetail::hdrToneMap(0.0f), 0.0f);
  EXPECT_EQ(flipdetail::hdrToneMap(-1.0f), 0.0f);
  EXPECT_LE(flipdetail::hdrToneMap(1e6f), 1.0f);
  // x_max: 0.16002 x^2 - 0.2829 x - 0.119 = 0 -> x = (0.2829 + sqrt(0.2829^2 + 4*0.16002*0.119)) / 0.32004
  // = 2.11886 (by hand, 5 digits).
  EXPECT_NEAR(flipdetail::hdrToneMapInverse(0.85), 2.11886, 5e-5);
  EXPECT_NEAR(flipdetail::hdrToneMap(float(flipdetail::hdrToneMapInverse(0.85))), 0.85, 1e-6);
}

TEST(HdrFlip, ExposureRangeFromTheReference) {
  // Grey pixels of luminance 0.25, 1 and 6 (BT.709 weights sum to 1): median 1, max 6.
  Image ref(3, 1, 3);
  const float lum[3] = {0.25f, 1.0f, 6.0f};
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 3; ++c) ref.at(x, 0, c) = lum[x];
  const auto r = flipdetail::exposureRange(ref);
  const double xMax = flipdetail::hdrToneMapInverse(0.85);
  EXPECT_NEAR(r.start, std::log2(xMax / 6.0), 1e-6);  // -1.5016: the maximum maps to 0.85
  EXPECT_NEAR(r.stop, std::log2(xMax / 1.0), 1e-6);   // 1.0833: the median maps to 0.85
  EXPECT_EQ(r.count, 3);                              // ceil(log2 6 = 2.585)
  const auto e = r.exposures();
  ASSERT_EQ(e.size(), 3u);
  EXPECT_NEAR(e[1], 0.5 * (r.start + r.stop), 1e-9);
  // A black reference: one exposure range at 0, and HDR-FLIP of black vs black is 0.
  const auto black = flipdetail::exposureRange(Image(4, 4, 3, 0.0f));
  EXPECT_EQ(black.start, 0.0);
  EXPECT_EQ(black.stop, 0.0);
  EXPECT_EQ(hdrFlip(Image(16, 16, 3, 0.0f), Image(16, 16, 3, 0.0f)), 0.0);
}

TEST(HdrFlip, IdenticalImagesGiveZeroAndNoiseRanksWorse) {
  // An HDR test image: a gradient over three decades with a bright patch.
  Image ref(48, 32, 3);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x)
      for (int c = 0; c < 3; ++c) ref.at(x, y, c) = 0.01f * std::pow(1000.0f, float(x) / 47.0f) * (1.0f + 0.1f * c);
  Image map;
  EXPECT_EQ(hdrFlip(ref, ref, {}, &map), 0.0);
  for (float v : map.pixels) EXPECT_EQ(v, 0.0f);
  const Image noise = pattern(48, 32, 3, 7);
  Image mild = ref, strong = ref;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    mild.pixels[i] *= 1.0f + 0.1f * (noise.pixels[i] - 0.5f);
    strong.pixels[i] *= 1.0f + 0.8f * (noise.pixels[i] - 0.5f);
  }
  const double eMild = hdrFlip(mild, ref), eStrong = hdrFlip(strong, ref);
  EXPECT_GT(eMild, 0.0);
  EXPECT_GT(eStrong, eMild);
  // The per-pixel error is the largest over the exposures, so it is never below LDR-FLIP of any
  // one exposure of the bracket (here the middle one, computed by hand from the parts).
  HdrFlipReference prepared(ref);
  Image hdrMap;
  prepared.compare(strong, &hdrMap);
  const double c = prepared.exposures()[prepared.exposures().size() / 2];
  Image refTm(48, 32, 3), testTm(48, 32, 3);
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    refTm.pixels[i] = flipdetail::hdrToneMap(ref.pixels[i] * float(std::exp2(c)));
    testTm.pixels[i] = flipdetail::hdrToneMap(strong.pixels[i] * float(std::exp2(c)));
  }
  Image ldrMap;
  FlipReference(refTm, {}, FlipInput::Linear).compare(testTm, &ldrMap);
  for (size_t i = 0; i < ldrMap.pixels.size(); ++i) EXPECT_GE(hdrMap.pixels[i], ldrMap.pixels[i]);
}

TEST(HdrFlip, SeesHighlightsTheToneMapClips) {
  // Highlights of 40 vs 80: after the ACES tone map at exposure 0 both are white, so LDR-FLIP on
  // the tone-mapped images hardly differs; the bracket's darkest exposure (the maximum at 0.85)
  // tells them apart.
  Image ref(32, 32, 3, 0.2f), test = ref;
  for (int y = 8; y < 24; ++y)
    for (int x = 8; x < 24; ++x)
      for (int c = 0; c < 3; ++c) ref.at(x, y, c) = 80.0f, test.at(x, y, c) = 40.0f;
  Image tmRef(32, 32, 3), tmTest(32, 32, 3);
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    tmRef.pixels[i] = std::min(1.0f, flipdetail::hdrToneMap(ref.pixels[i]));
    tmTest.pixels[i] = std::min(1.0f, flipdetail::hdrToneMap(test.pixels[i]));
  }
  const double ldr = FlipReference(tmRef, {}, FlipInput::Linear).compare(tmTest);
  const double hdr = hdrFlip(test, ref);
  EXPECT_LT(ldr, 0.01);
  EXPECT_GT(hdr, 10 * ldr);
}

TEST(Flip, PixelsPerDegreeOptionAndErrorStatistics) {
  FlipSettings s;
  s.ppd = 30;
  EXPECT_EQ(s.pixelsPerDegree(), 30.0);
  int r = 0;
  flipdetail::csfKernel(0, s.pixelsPerDegree(), &r);
  EXPECT_EQ(r, 5);  // ceil(3 sqrt(0.04 / (2 pi^2)) 30) = ceil(4.05)
  // Quartiles as numpy.percentile: {0..4} -> 1, 2, 3; {0..3} -> 0.75, 1.5, 2.25.
  Image a(5, 1, 1), b(4, 1, 1);
  for (int i = 0; i < 5; ++i) a.pixels[size_t(i)] = float(4 - i);
  for (int i = 0; i < 4; ++i) b.pixels[size_t(i)] = float(i);
  const auto sa = errorStatistics(a), sb = errorStatistics(b);
  EXPECT_DOUBLE_EQ(sa.mean, 2.0);
  EXPECT_DOUBLE_EQ(sa.q1, 1.0);
  EXPECT_DOUBLE_EQ(sa.median, 2.0);
  EXPECT_DOUBLE_EQ(sa.q3, 3.0);
  EXPECT_DOUBLE_EQ(sb.q1, 0.75);
  EXPECT_DOUBLE_EQ(sb.median, 1.5);
  EXPECT_DOUBLE_EQ(sb.q3, 2.25);
}
