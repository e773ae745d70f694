// Image metrics (see include/rtd/eval/metrics.h and docs/evaluation.md).
#include "rtd/eval/metrics.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "eval/filter.h"
#include "passes/tonemap.h"
#include "rtd/error.h"

namespace rtd::eval {

namespace {

void requireSameSize(const Image& a, const Image& b, const char* what) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw Error(std::string(what) + ": image sizes differ (" + std::to_string(a.width) + "x" +
                std::to_string(a.height) + "x" + std::to_string(a.channels) + " vs " + std::to_string(b.width) +
                "x" + std::to_string(b.height) + "x" + std::to_string(b.channels) + ")");
  if (a.empty()) throw Error(std::string(what) + ": empty image");
}

/// Sum over all pixel values of f(test, reference), in double, parallel over rows.
template <class F>
double sumOver(const Image& a, const Image& b, F f) {
  const size_t rowLen = size_t(a.width) * a.channels;
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, a.height), 0.0,
      [&](const tbb::blocked_range<int>& r, double acc) {
        for (int y = r.begin(); y < r.end(); ++y) {
          const float* pa = a.pixels.data() + y * rowLen;
          const float* pb = b.pixels.data() + y * rowLen;
          double row = 0;
          for (size_t i = 0; i < rowLen; ++i) row += f(double(pa[i]), double(pb[i]));
          acc += row;
        }
        return acc;
      },
      std::plus<double>());
}

tonemap::Operator internalOperator(ToneMapSettings::Operator op) {
  switch (op) {
    case ToneMapSettings::Operator::Clamp: return tonemap::Operator::Clamp;
    case ToneMapSettings::Operator::Reinhard: return tonemap::Operator::Reinhard;
    default: return tonemap::Operator::Aces;
  }
}

}  // namespace

std::string operatorName(ToneMapSettings::Operator op) {
  switch (op) {
    case ToneMapSettings::Operator::Clamp: return "clamp";
    case ToneMapSettings::Operator::Reinhard: return "reinhard";
    default: return "aces";
  }
}

ToneMapSettings::Operator parseOperator(const std::string& name) {
  if (name == "clamp") return ToneMapSettings::Operator::Clamp;
  if (name == "reinhard") return ToneMapSettings::Operator::Reinhard;
  if (name == "aces") return ToneMapSettings::Operator::Aces;
  throw Error("tone map '" + name + "': expected clamp, reinhard or aces");
}

Image toneMap(const Image& linear, const ToneMapSettings& tm) {
  if (linear.channels < 3) throw Error("toneMap: expected an RGB image, got " + std::to_string(linear.channels) + " channel(s)");
  Image out(linear.width, linear.height, 3);
  const auto op = internalOperator(tm.op);
  const float scale = std::exp2(tm.exposure);
  tbb::parallel_for(0, linear.height, [&](int y) {
    for (int x = 0; x < linear.width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = tonemap::toneMapToSrgb(linear.at(x, y, c), op, scale);
  });
  return out;
}

Image luminance(const Image& rgb) {
  if (rgb.channels < 3) throw Error("luminance: expected an RGB image");
  Image out(rgb.width, rgb.height, 1);
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < rgb.width; ++x) {
      const float* p = rgb.pixel(x, y);
      out.at(x, y) = tonemap::luminance(p[0], p[1], p[2]);
    }
  return out;
}

double mse(const Image& a, const Image& b) {
  requireSameSize(a, b, "mse");
  return sumOver(a, b, [](double x, double r) { return (x - r) * (x - r); }) / double(a.pixels.size());
}

double psnr(const Image& test, const Image& reference, double peak) {
  const double m = mse(test, reference);
  return m == 0.0 ? kInfinity : 10.0 * std::log10(peak * peak / m);
}

double rmse(const Image& test, const Image& reference) { return std::sqrt(mse(test, reference)); }

double relMse(const Image& test, const Image& reference, double epsilon) {
  requireSameSize(test, reference, "relMse");
  return sumOver(test, reference, [epsilon](double x, double r) { return (x - r) * (x - r) / (r * r + epsilon); }) /
         double(test.pixels.size());
}

// ---------------------------------------------------------------------------------------------
// SSIM, Wang et al. 2004, eq. 13 with the Gaussian-weighted statistics of Sec. III-C.

double ssim(const Image& test, const Image& reference, double dataRange, Image* map) {
  requireSameSize(test, reference, "ssim");
  const int w = test.width, h = test.height, nc = test.channels;
  constexpr double sigma = 1.5;
  constexpr int radius = 5;  // 11x11 window
  std::vector<double> g(2 * radius + 1);
  double gs = 0;
  for (int k = -radius; k <= radius; ++k) gs += g[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  for (double& v : g) v /= gs;
  const double c1 = (0.01 * dataRange) * (0.01 * dataRange), c2 = (0.03 * dataRange) * (0.03 * dataRange);

  // Interior: pixels whose full window is inside the image; the whole image if there are none.
  const bool interior = w > 2 * radius && h > 2 * radius;
  const int x0 = interior ? radius : 0, x1 = interior ? w - radius : w;
  const int y0 = interior ? radius : 0, y1 = interior ? h - radius : h;

  const size_t n = size_t(w) * h;
  std::vector<double> a(n), b(n), prod(n), mua, mub, saa, sbb, sab, tmp;
  if (map) *map = Image(w, h, 1, 0.0f);
  double total = 0;
  for (int c = 0; c < nc; ++c) {
    for (size_t i = 0; i < n; ++i) {
      a[i] = test.pixels[i * nc + c];
      b[i] = reference.pixels[i * nc + c];
    }
    detail::convolveSeparable(a, mua, tmp, w, h, g, g);
    detail::convolveSeparable(b, mub, tmp, w, h, g, g);
    for (size_t i = 0; i < n; ++i) prod[i] = a[i] * a[i];
    detail::convolveSeparable(prod, saa, tmp, w, h, g, g);
    for (size_t i = 0; i < n; ++i) prod[i] = b[i] * b[i];
    detail::convolveSeparable(prod, sbb, tmp, w, h, g, g);
    for (size_t i = 0; i < n; ++i) prod[i] = a[i] * b[i];
    detail::convolveSeparable(prod, sab, tmp, w, h, g, g);
    double sum = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        const double ma = mua[i], mb = mub[i];
        const double va = saa[i] - ma * ma, vb = sbb[i] - mb * mb, cov = sab[i] - ma * mb;
        const double s = ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
        if (x >= x0 && x < x1 && y >= y0 && y < y1) sum += s;
        if (map) map->pixels[i] += float(s / nc);
      }
    total += sum / (double(x1 - x0) * (y1 - y0));
  }
  return total / nc;
}

// ---------------------------------------------------------------------------------------------
// FLIP, Andersson et al. 2020 (LDR). Section numbers refer to the paper; constants are listed
// in docs/evaluation.md.

double FlipSettings::pixelsPerDegree() const {
  if (ppd > 0) return ppd;
  return monitorDistance * (monitorResolutionX / monitorWidth) * (std::numbers::pi / 180.0);
}

namespace flipdetail {
namespace {
// Linear sRGB (D65) <-> XYZ, from the sRGB primaries (IEC 61966-2-1) as exact fractions.
constexpr double kRgbToXyz[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};

struct Matrices {
  double xyzToRgb[3][3];
  double white[3];  // XYZ of linear RGB (1, 1, 1): the reference white of YyCxCz and L*a*b*
  Matrices() {
    const auto& m = kRgbToXyz;
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        // Cofactor transpose / determinant.
        const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
        xyzToRgb[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
      }
    for (int i = 0; i < 3; ++i) white[i] = m[i][0] + m[i][1] + m[i][2];
  }
};
const Matrices& mats() {
  static const Matrices m;
  return m;
}

void rgbToXyz(const float rgb[3], double xyz[3]) {
  for (int i = 0; i < 3; ++i) xyz[i] = kRgbToXyz[i][0] * rgb[0] + kRgbToXyz[i][1] * rgb[1] + kRgbToXyz[i][2] * rgb[2];
}

double labF(double t) {
  constexpr double delta = 6.0 / 29.0;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
}

// Spatial contrast sensitivity functions (Sec. 4.1, eq. 2): per channel the sum of two
// Gaussians a_k sqrt(pi / b_k) exp(-pi^2 x^2 / b_k), x in degrees.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsf[3] = {{1.0, 0.0047, 0.0, 1e-5},     // achromatic (Yy)
                         {1.0, 0.0053, 0.0, 1e-5},     // red-green (Cx)
                         {34.1, 0.04, 13.5, 0.025}};   // blue-yellow (Cz)
int csfRadius(double ppd) {
  // Three standard deviations of the widest Gaussian (b = 0.04): sigma = sqrt(b / (2 pi^2)) deg.
  const double maxB = 0.04;
  return int(std::ceil(3.0 * std::sqrt(maxB / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
}
std::vector<double> gauss1d(double b, double ppd, int r) {
  std::vector<double> g(2 * r + 1);
  for (int k = -r; k <= r; ++k) {
    const double xDeg = k / ppd;
    g[k + r] = std::exp(-std::numbers::pi * std::numbers::pi * xDeg * xDeg / b);
  }
  return g;
}

constexpr double kQc = 0.7, kPc = 0.4, kPt = 0.95;  // colour compression (Sec. 4.1)
constexpr double kFeatureWidth = 0.082;             // degrees (Sec. 4.2)
constexpr double kQf = 0.5;                         // feature exponent (Sec. 4.2)
}  // namespace

void linearRgbToYCxCz(const float rgb[3], float out[3]) {
  double xyz[3];
  rgbToXyz(rgb, xyz);
  const auto& w = mats().white;
  const double xr = xyz[0] / w[0], yr = xyz[1] / w[1], zr = xyz[2] / w[2];
  out[0] = float(116.0 * yr - 16.0);
  out[1] = float(500.0 * (xr - yr));
  out[2] = float(200.0 * (yr - zr));
}

void ycxczToLinearRgb(const float in[3], float rgb[3]) {
  const auto& m = mats();
  const double yr = (in[0] + 16.0) / 116.0;
  const double xr = in[1] / 500.0 + yr, zr = yr - in[2] / 200.0;
  const double xyz[3] = {xr * m.white[0], yr * m.white[1], zr * m.white[2]};
  for (int i = 0; i < 3; ++i)
    rgb[i] = float(m.xyzToRgb[i][0] * xyz[0] + m.xyzToRgb[i][1] * xyz[1] + m.xyzToRgb[i][2] * xyz[2]);
}

void linearRgbToLab(const float rgb[3], float lab[3]) {
  double xyz[3];
  rgbToXyz(rgb, xyz);
  const auto& w = mats().white;
  const double fx = labF(xyz[0] / w[0]), fy = labF(xyz[1] / w[1]), fz = labF(xyz[2] / w[2]);
  lab[0] = float(116.0 * fy - 16.0);
  lab[1] = float(500.0 * (fx - fy));
  lab[2] = float(200.0 * (fy - fz));
}

void hunt(float lab[3]) {
  lab[1] *= 0.01f * lab[0];
  lab[2] *= 0.01f * lab[0];
}

double hyab(const float p[3], const float q[3]) {
  const double dl = double(p[0]) - q[0], da = double(p[1]) - q[1], db = double(p[2]) - q[2];
  return std::abs(dl) + std::sqrt(da * da + db * db);
}

double maxColorDistance() {
  static const double cmax = [] {
    const float green[3] = {0, 1, 0}, blue[3] = {0, 0, 1};
    float lg[3], lb[3];
    linearRgbToLab(green, lg);
    linearRgbToLab(blue, lb);
    hunt(lg);
    hunt(lb);
    return hyab(lg, lb);
  }();
  return cmax;
}

double compressColorError(double distance) {
  const double cmax = std::pow(maxColorDistance(), kQc);
  const double e = std::pow(distance, kQc);
  const double knee = kPc * cmax;
  const double v = e < knee ? e * kPt / knee : kPt + (e - knee) / (cmax - knee) * (1.0 - kPt);
  return std::min(v, 1.0);  // c_max is the largest in-gamut distance; the clamp only guards rounding
}

std::vector<float> csfKernel(int channel, double ppd, int* radius) {
  const int r = csfRadius(ppd);
  const Csf& p = kCsf[channel];
  std::vector<float> k(size_t(2 * r + 1) * (2 * r + 1));
  double sum = 0;
  for (int y = -r; y <= r; ++y)
    for (int x = -r; x <= r; ++x) {
      const double d2 = (double(x) * x + double(y) * y) / (ppd * ppd);
      const double pi2 = std::numbers::pi * std::numbers::pi;
      const double v = p.a1 * std::sqrt(std::numbers::pi / p.b1) * std::exp(-pi2 * d2 / p.b1) +
                       p.a2 * std::sqrt(std::numbers::pi / p.b2) * std::exp(-pi2 * d2 / p.b2);
      k[size_t(y + r) * (2 * r + 1) + (x + r)] = float(v);
      sum += v;
    }
  for (float& v : k) v = float(v / sum);
  if (radius) *radius = r;
  return k;
}

double featureSigma(double ppd) { return 0.5 * kFeatureWidth * ppd; }

}  // namespace flipdetail

/// Spatially filtered, Hunt-adjusted L*a*b* of one image (Sec. 4.1) and its normalized
/// achromatic channel's feature magnitudes (Sec. 4.2).
struct FlipReference::Prepared {
  std::vector<float> lab[3];
  std::vector<float> edge, point;  // feature magnitudes
};
using FlipPrepared = FlipReference::Prepared;

namespace {
using namespace flipdetail;

FlipPrepared prepare(const Image& image, double ppd, FlipInput input) {
  const int w = image.width, h = image.height;
  const size_t n = size_t(w) * h;
  std::vector<float> ycc[3], gray(n);
  for (auto& c : ycc) c.resize(n);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const float* p = image.pixel(x, y);
      const bool srgb = input == FlipInput::Srgb;
      const float lin[3] = {srgb ? tonemap::srgbDecode(p[0]) : std::clamp(p[0], 0.0f, 1.0f),
                            srgb ? tonemap::srgbDecode(p[1]) : std::clamp(p[1], 0.0f, 1.0f),
                            srgb ? tonemap::srgbDecode(p[2]) : std::clamp(p[2], 0.0f, 1.0f)};
      float o[3];
      linearRgbToYCxCz(lin, o);
      for (int c = 0; c < 3; ++c) ycc[c][i] = o[c];
      gray[i] = (o[0] + 16.0f) / 116.0f;  // Yy normalized to [0, 1] (= Y / Y_white)
    }
  });

  // CSF filtering, each Gaussian term separably: kernel = (t1 g1 x g1 + t2 g2 x g2) / sum.
  const int r = csfRadius(ppd);
  std::vector<float> filtered[3], tmp, part;
  for (int c = 0; c < 3; ++c) {
    const Csf& p = kCsf[c];
    const auto g1d = gauss1d(p.b1, ppd, r), g2d = gauss1d(p.b2, ppd, r);
    double s1 = 0, s2 = 0;
    for (double v : g1d) s1 += v;
    for (double v : g2d) s2 += v;
    const double t1 = p.a1 * std::sqrt(std::numbers::pi / p.b1), t2 = p.a2 * std::sqrt(std::numbers::pi / p.b2);
    const double total = t1 * s1 * s1 + t2 * s2 * s2;
    std::vector<float> g1(g1d.size()), g1y(g1d.size());
    for (size_t k = 0; k < g1d.size(); ++k) {
      g1[k] = float(g1d[k]);
      g1y[k] = float(g1d[k] * t1 / total);
    }
    detail::convolveSeparable(ycc[c], filtered[c], tmp, w, h, g1, g1y);
    if (t2 > 0) {
      std::vector<float> g2(g2d.size()), g2y(g2d.size());
      for (size_t k = 0; k < g2d.size(); ++k) {
        g2[k] = float(g2d[k]);
        g2y[k] = float(g2d[k] * t2 / total);
      }
      detail::convolveSeparable(ycc[c], part, tmp, w, h, g2, g2y);
      for (size_t i = 0; i < n; ++i) filtered[c][i] += part[i];
    }
  }

  FlipPrepared out;
  for (auto& c : out.lab) c.resize(n);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const float o[3] = {filtered[0][i], filtered[1][i], filtered[2][i]};
      float rgb[3], lab[3];
      ycxczToLinearRgb(o, rgb);
      for (float& v : rgb) v = std::clamp(v, 0.0f, 1.0f);
      linearRgbToLab(rgb, lab);
      hunt(lab);
      for (int c = 0; c < 3; ++c) out.lab[c][i] = lab[c];
    }
  });

  // Feature detection (Sec. 4.2): first (edge) and second (point) derivatives of a Gaussian of
  // std. dev. 0.5 * 0.082 deg * ppd pixels; positive weights normalized to sum 1 and negative
  // weights to -1. Each 2D kernel is separable: d(x) * g(y) with g normalized to sum 1.
  const double sd = featureSigma(ppd);
  const int fr = int(std::ceil(3.0 * sd));
  std::vector<float> g(2 * fr + 1), d1(2 * fr + 1), d2(2 * fr + 1);
  double gsum = 0, d1pos = 0, d1neg = 0, d2pos = 0, d2neg = 0;
  for (int k = -fr; k <= fr; ++k) {
    const double gv = std::exp(-double(k) * k / (2 * sd * sd));
    const double e = -k * gv, p = (double(k) * k / (sd * sd) - 1.0) * gv;
    g[k + fr] = float(gv);
    d1[k + fr] = float(e);
    d2[k + fr] = float(p);
    gsum += gv;
    (e > 0 ? d1pos : d1neg) += std::abs(e);
    (p > 0 ? d2pos : d2neg) += std::abs(p);
  }
  for (int k = 0; k <= 2 * fr; ++k) {
    g[k] = float(g[k] / gsum);
    d1[k] = float(d1[k] / (d1[k] > 0 ? d1pos : d1neg));
    d2[k] = float(d2[k] / (d2[k] > 0 ? d2pos : d2neg));
  }
  std::vector<float> ex, ey, px, py;
  detail::convolveSeparable(gray, ex, tmp, w, h, d1, g);
  detail::convolveSeparable(gray, ey, tmp, w, h, g, d1);
  detail::convolveSeparable(gray, px, tmp, w, h, d2, g);
  detail::convolveSeparable(gray, py, tmp, w, h, g, d2);
  out.edge.resize(n);
  out.point.resize(n);
  for (size_t i = 0; i < n; ++i) {
    out.edge[i] = std::sqrt(ex[i] * ex[i] + ey[i] * ey[i]);
    out.point[i] = std::sqrt(px[i] * px[i] + py[i] * py[i]);
  }
  return out;
}
}  // namespace

FlipReference::FlipReference(const Image& reference, const FlipSettings& settings, FlipInput input)
    : settings_(settings), input_(input), width_(reference.width), height_(reference.height) {
  if (reference.channels != 3 || reference.empty()) throw Error("flip: expected a tone-mapped RGB reference (3 channels)");
  prepared_ = std::make_shared<const Prepared>(prepare(reference, settings.pixelsPerDegree(), input));
}

double FlipReference::compare(const Image& test, Image* errorMap) const {
  using namespace flipdetail;
  if (!prepared_) throw Error("flip: no reference prepared");
  if (test.width != width_ || test.height != height_ || test.channels != 3)
    throw Error("flip: test image is " + std::to_string(test.width) + "x" + std::to_string(test.height) + "x" +
                std::to_string(test.channels) + ", reference is " + std::to_string(width_) + "x" +
                std::to_string(height_) + "x3");
  const FlipPrepared t = prepare(test, settings_.pixelsPerDegree(), input_);
  const FlipPrepared& r = *prepared_;
  const int w = width_, h = height_;
  if (errorMap) *errorMap = Image(w, h, 1);
  std::vector<double> rowSums(h);
  tbb::parallel_for(0, h, [&](int y) {
    double rowSum = 0;
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const float lt[3] = {t.lab[0][i], t.lab[1][i], t.lab[2][i]};
      const float lr[3] = {r.lab[0][i], r.lab[1][i], r.lab[2][i]};
      const double colorError = compressColorError(hyab(lt, lr));
      const double featureDiff = std::max(std::abs(double(t.edge[i]) - r.edge[i]), std::abs(double(t.point[i]) - r.point[i]));
      const double featureError = std::pow(featureDiff / std::numbers::sqrt2, kQf);
      const double e = std::pow(colorError, 1.0 - featureError);  // Sec. 4.3
      if (errorMap) errorMap->pixels[i] = float(e);
      rowSum += e;
    }
    rowSums[y] = rowSum;
  });
  double sum = 0;
  for (double s : rowSums) sum += s;
  return sum / (double(w) * h);
}

double flip(const Image& test, const Image& reference, const FlipSettings& settings, Image* errorMap) {
  requireSameSize(test, reference, "flip");
  if (test.channels != 3) throw Error("flip: expected tone-mapped RGB images (3 channels)");
  return FlipReference(reference, settings).compare(test, errorMap);
}

// ---------------------------------------------------------------------------------------------
// HDR-FLIP, Andersson et al. 2021: LDR-FLIP over an exposure bracket of the reference's range.

namespace flipdetail {
namespace {
// FLIP's ACES curve: Narkowicz's fit of 0.6 x, as a ratio of quadratics (a x^2 + b x + c) / (d x^2 + e x + f).
constexpr double kTa = 0.6 * 0.6 * 2.51, kTb = 0.6 * 0.03, kTc = 0.0, kTd = 0.6 * 0.6 * 2.43, kTe = 0.6 * 0.59, kTf = 0.14;
constexpr double kExposureTarget = 0.85;  // start/stop exposures map L_max/L_median to this
constexpr double kMaxStops = 12.0;        // a zero median: at most this many stops below L_max

float relativeLuminance(const float* p) {
  const auto v = [](float c) { return std::isfinite(c) ? std::max(c, 0.0f) : 0.0f; };
  return tonemap::luminance(v(p[0]), v(p[1]), v(p[2]));
}
}  // namespace

float hdrToneMap(float x) {
  const double v = std::isfinite(x) ? std::max(double(x), 0.0) : 0.0;
  return float(std::clamp((kTa * v * v + kTb * v + kTc) / (kTd * v * v + kTe * v + kTf), 0.0, 1.0));
}

double hdrToneMapInverse(double y) {
  // (a - y d) x^2 + (b - y e) x + (c - y f) = 0; the positive root.
  const double a = kTa - y * kTd, b = kTb - y * kTe, c = kTc - y * kTf;
  return (-b + std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
}

std::vector<double> ExposureRange::exposures() const {
  std::vector<double> e(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) e[size_t(i)] = start + (stop - start) * i / double(std::max(count - 1, 1));
  return e;
}

ExposureRange exposureRange(const Image& reference) {
  std::vector<float> lum(size_t(reference.width) * reference.height);
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x) lum[size_t(y) * reference.width + x] = relativeLuminance(reference.pixel(x, y));
  ExposureRange r;
  if (lum.empty()) return r;
  const double maxL = *std::max_element(lum.begin(), lum.end());
  const size_t n = lum.size();
  std::nth_element(lum.begin(), lum.begin() + n / 2, lum.end());
  double median = lum[n / 2];
  if (n % 2 == 0) median = 0.5 * (median + *std::max_element(lum.begin(), lum.begin() + n / 2));
  if (!(maxL > 0)) return r;  // black: one exposure range [0, 0]
  median = std::max(median, maxL * std::exp2(-kMaxStops));
  const double xMax = hdrToneMapInverse(kExposureTarget);
  r.start = std::log2(xMax / maxL);
  r.stop = std::log2(xMax / median);
  r.count = std::max(2, int(std::ceil(r.stop - r.start)));
  return r;
}
}  // namespace flipdetail

namespace {
/// The reference or test image at exposure c through HDR-FLIP's tone curve (display-linear).
Image exposed(const Image& hdr, double exposure) {
  if (hdr.channels < 3) throw Error("hdrFlip: expected an RGB image, got " + std::to_string(hdr.channels) + " channel(s)");
  Image out(hdr.width, hdr.height, 3);
  const float scale = float(std::exp2(exposure));
  tbb::parallel_for(0, hdr.height, [&](int y) {
    for (int x = 0; x < hdr.width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = flipdetail::hdrToneMap(hdr.at(x, y, c) * scale);
  });
  return out;
}
}  // namespace

HdrFlipReference::HdrFlipReference(const Image& reference, const FlipSettings& settings)
    : exposures_(flipdetail::exposureRange(reference).exposures()) {
  for (double c : exposures_) references_.emplace_back(exposed(reference, c), settings, FlipInput::Linear);
}

double HdrFlipReference::compare(const Image& test, Image* errorMap, Image* exposureMap) const {
  if (empty()) throw Error("hdrFlip: no reference prepared");
  Image best, map;
  for (size_t k = 0; k < exposures_.size(); ++k) {
    references_[k].compare(exposed(test, exposures_[k]), &map);
    if (k == 0) {
      best = map;
      if (exposureMap) *exposureMap = Image(map.width, map.height, 1, 0.0f);
      continue;
    }
    for (size_t i = 0; i < map.pixels.size(); ++i)
      if (map.pixels[i] > best.pixels[i]) {
        best.pixels[i] = map.pixels[i];
        if (exposureMap) exposureMap->pixels[i] = float(k) / float(exposures_.size() - 1);
      }
  }
  double sum = 0;
  for (float v : best.pixels) sum += v;
  const double mean = sum / double(best.pixels.size());
  if (errorMap) *errorMap = std::move(best);
  return mean;
}

double hdrFlip(const Image& test, const Image& reference, const FlipSettings& settings, Image* errorMap) {
  if (test.width != reference.width || test.height != reference.height)
    throw Error("hdrFlip: image sizes differ (" + std::to_string(test.width) + "x" + std::to_string(test.height) + " vs " +
                std::to_string(reference.width) + "x" + std::to_string(reference.height) + ")");
  return HdrFlipReference(reference, settings).compare(test, errorMap);
}

ErrorStatistics errorStatistics(const Image& map) {
  ErrorStatistics s;
  const size_t n = size_t(map.width) * map.height;
  if (n == 0) return s;
  std::vector<float> v(n);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) sum += v[i] = map.pixels[i * map.channels];
  s.mean = sum / double(n);
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) {  // numpy.percentile's default ('linear')
    const double pos = q * double(n - 1);
    const size_t lo = size_t(pos), hi = std::min(lo + 1, n - 1);
    return double(v[lo]) + (pos - double(lo)) * (double(v[hi]) - double(v[lo]));
  };
  s.q1 = at(0.25);
  s.median = at(0.5);
  s.q3 = at(0.75);
  return s;
}

// ---------------------------------------------------------------------------------------------

void magma(float v, float rgb[3]) {
  // Eleven samples (t = 0, 0.1, ..., 1) of matplotlib's magma map, linearly interpolated.
  static constexpr float kMagma[11][3] = {
      {0.001f, 0.000f, 0.014f}, {0.079f, 0.054f, 0.212f}, {0.232f, 0.060f, 0.438f}, {0.390f, 0.100f, 0.502f},
      {0.550f, 0.161f, 0.506f}, {0.716f, 0.215f, 0.475f}, {0.869f, 0.288f, 0.409f}, {0.968f, 0.440f, 0.360f},
      {0.995f, 0.624f, 0.427f}, {0.996f, 0.813f, 0.573f}, {0.987f, 0.991f, 0.750f}};
  const float t = std::clamp(std::isfinite(v) ? v : 1.0f, 0.0f, 1.0f) * 10.0f;
  const int i = std::min(int(t), 9);
  const float f = t - float(i);
  for (int c = 0; c < 3; ++c) rgb[c] = kMagma[i][c] + f * (kMagma[i + 1][c] - kMagma[i][c]);
}

Image colorize(const Image& map) {
  Image out(map.width, map.height, 3);
  for (size_t i = 0; i < size_t(map.width) * map.height; ++i) magma(map.pixels[i * map.channels], &out.pixels[i * 3]);
  return out;
}

}  // namespace rtd::eval
