// rtdenoise evaluation — image metrics on rtd::Image. Every function states the colour space it
// expects; docs/evaluation.md gives the definitions, constants and their sources.
//
//   linear HDR (scene-referred radiance, what denoisers output): relMse, rmse
//   tone-mapped sRGB (toneMap() output, values in [0,1]):          psnr, ssim, flip, temporal error
#pragma once
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rtd/error.h"
#include "rtd/image.h"

namespace rtd::eval {

/// How linear HDR radiance becomes a display-referred sRGB image for the LDR metrics.
struct ToneMapSettings {
  enum class Operator { Clamp, Reinhard, Aces };
  /// Default ACES filmic fit (Narkowicz 2015): a curve real-time renderers ship with.
  Operator op = Operator::Aces;
  /// Exposure in stops: radiance is multiplied by 2^exposure before the curve.
  float exposure = 0.0f;
};
std::string operatorName(ToneMapSettings::Operator op);
/// "clamp", "reinhard" or "aces"; throws rtd::Error otherwise.
ToneMapSettings::Operator parseOperator(const std::string& name);

/// Linear HDR RGB(A) -> tone-mapped, sRGB-encoded RGB in [0,1] (3 channels; alpha dropped).
Image toneMap(const Image& linear, const ToneMapSettings& tm = {});

/// Luminance (BT.709 weights) of each pixel of an RGB image, one channel.
Image luminance(const Image& rgb);

/// Mean squared error over all pixels and channels (any space; double accumulation).
double mse(const Image& a, const Image& b);

/// Peak signal-to-noise ratio in dB, 10 log10(peak^2 / MSE), over all channels. Intended for
/// tone-mapped sRGB images with peak 1. +infinity for identical images.
double psnr(const Image& test, const Image& reference, double peak = 1.0);

/// Root mean squared error on linear HDR radiance, over all channels.
double rmse(const Image& test, const Image& reference);

/// Relative MSE on linear HDR radiance: mean over pixels and channels of
/// (test - ref)^2 / (ref^2 + epsilon) (Rousselle et al. 2011; epsilon 0.01 as in BMFR/SVGF work).
double relMse(const Image& test, const Image& reference, double epsilon = 0.01);

/// SSIM (Wang et al. 2004) with an 11x11 Gaussian window of sigma 1.5, K1 = 0.01, K2 = 0.03,
/// dynamic range L = `dataRange`, population (not sample) covariances. Computed per channel and
/// averaged over channels; the mean is taken over the pixels whose whole window lies inside the
/// image (as Wang's reference code and scikit-image do). Intended for tone-mapped sRGB in [0,1].
/// `map`, if not null, receives the per-pixel SSIM averaged over channels (edge-clamped window
/// outside the interior).
double ssim(const Image& test, const Image& reference, double dataRange = 1.0, Image* map = nullptr);

/// FLIP viewing conditions: pixels per degree of visual angle. The paper's default is a 0.7 m
/// wide 3840-pixel monitor seen from 0.7 m: 0.7 * (3840 / 0.7) * pi / 180 = 67.02 ppd.
struct FlipSettings {
  double monitorDistance = 0.7;  ///< metres
  double monitorWidth = 0.7;     ///< metres
  double monitorResolutionX = 3840;
  /// Pixels per degree given directly; 0: from the monitor above.
  double ppd = 0;
  double pixelsPerDegree() const;
};

/// How FLIP's input images are encoded: sRGB-encoded display values (LDR-FLIP on a tone-mapped
/// image) or display-linear values in [0,1] (HDR-FLIP's exposures: tone-mapped, not encoded).
enum class FlipInput { Srgb, Linear };

/// LDR-FLIP (Andersson et al. 2020) of two tone-mapped sRGB images in [0,1] (3 channels).
/// Returns the mean of the per-pixel error; `errorMap`, if not null, receives the per-pixel
/// error in [0,1] (one channel).
double flip(const Image& test, const Image& reference, const FlipSettings& settings = {},
            Image* errorMap = nullptr);

/// The reference half of FLIP (filtered L*a*b* and feature magnitudes), computed once and
/// compared against several test images (one per method) at the cost of one preparation each.
class FlipReference {
 public:
  FlipReference() = default;
  FlipReference(const Image& reference, const FlipSettings& settings = {}, FlipInput input = FlipInput::Srgb);
  /// Same as flip(test, reference, settings, errorMap); `test` encoded as the reference was.
  double compare(const Image& test, Image* errorMap = nullptr) const;
  bool empty() const { return !prepared_; }
  struct Prepared;

 private:
  std::shared_ptr<const Prepared> prepared_;
  FlipSettings settings_;
  FlipInput input_ = FlipInput::Srgb;
  int width_ = 0, height_ = 0;
};

/// HDR-FLIP (Andersson et al. 2021, "Visualizing Errors in Rendered High Dynamic Range Images")
/// of linear HDR RGB images: LDR-FLIP at several exposures c (image x 2^c, FLIP's ACES tone
/// curve, clamped to [0,1], not sRGB-encoded), spaced evenly from the exposure at which the
/// reference's largest luminance maps to 0.85 to the one at which its median luminance does;
/// the per-pixel error is the largest over the exposures. docs/evaluation.md has the details.
double hdrFlip(const Image& test, const Image& reference, const FlipSettings& settings = {},
               Image* errorMap = nullptr);

/// The reference half of HDR-FLIP: its exposures, each prepared as a FlipReference.
class HdrFlipReference {
 public:
  HdrFlipReference() = default;
  explicit HdrFlipReference(const Image& referenceHdr, const FlipSettings& settings = {});
  /// Same as hdrFlip(test, reference, settings, errorMap). `exposureMap`, if not null, receives
  /// per pixel the index of the exposure that gave the largest error, over (count - 1).
  double compare(const Image& testHdr, Image* errorMap = nullptr, Image* exposureMap = nullptr) const;
  bool empty() const { return exposures_.empty(); }
  /// The exposures c (stops), from the start exposure to the stop exposure.
  const std::vector<double>& exposures() const { return exposures_; }

 private:
  std::vector<double> exposures_;
  std::vector<FlipReference> references_;
};

/// The distribution of a per-pixel error map (one channel): mean, and the first quartile,
/// median and third quartile (linearly interpolated between ranks, as numpy.percentile).
struct ErrorStatistics {
  double mean = 0, q1 = 0, median = 0, q3 = 0;
};
ErrorStatistics errorStatistics(const Image& map);

/// The magma colour map (as the FLIP paper shows error maps), v in [0,1] -> sRGB-encoded RGB.
void magma(float v, float rgb[3]);
/// A one-channel map in [0,1] -> sRGB-encoded RGB image through magma().
Image colorize(const Image& map);

/// FLIP internals, exposed for tests against the paper's definitions.
namespace flipdetail {
/// Linear sRGB -> CIE XYZ (D65), then the opponent space YyCxCz of Andersson et al. (Sec. 4.1).
void linearRgbToYCxCz(const float rgb[3], float ycxcz[3]);
void ycxczToLinearRgb(const float ycxcz[3], float rgb[3]);
/// Linear sRGB -> CIELAB (D65 white = XYZ of linear RGB (1,1,1)).
void linearRgbToLab(const float rgb[3], float lab[3]);
/// Hunt adjustment (Sec. 4.1): a and b scaled by 0.01 L.
void hunt(float lab[3]);
/// HyAB distance (Abasi et al. 2020): |dL| + sqrt(da^2 + db^2).
double hyab(const float lab1[3], const float lab2[3]);
/// Colour error in [0,1] from a HyAB distance of Hunt-adjusted colours (Sec. 4.1: exponent
/// q_c = 0.7, c_max from green/blue, p_c = 0.4, p_t = 0.95).
double compressColorError(double hyabDistance);
/// c_max: HyAB distance between Hunt-adjusted pure green and pure blue.
double maxColorDistance();
/// 1D kernel radius and weights of the spatial CSF of channel c (0 Yy, 1 Cx, 2 Cz) at `ppd`:
/// weights of the 2D filter along one axis before normalization are not separable for Cz (a
/// sum of two Gaussians); this returns the normalized 2D kernel, row-major, side 2r+1.
std::vector<float> csfKernel(int channel, double ppd, int* radius);
/// Feature detector standard deviation in pixels: 0.5 * 0.082 deg * ppd (Sec. 4.2).
double featureSigma(double ppd);

/// HDR-FLIP's tone curve: the ACES fit of Narkowicz applied to 0.6 x (as the FLIP paper's
/// implementation does), (0.36*2.51 x^2 + 0.6*0.03 x) / (0.36*2.43 x^2 + 0.6*0.59 x + 0.14),
/// clamped to [0, 1].
float hdrToneMap(float x);
/// The x >= 0 with hdrToneMap(x) = y, for y in (0, 1): the positive root of the quadratic.
double hdrToneMapInverse(double y);
/// Start and stop exposures and their count (HDR-FLIP): with x_max = hdrToneMapInverse(0.85),
/// start = log2(x_max / L_max), stop = log2(x_max / L_median) over the reference's luminances
/// L (BT.709 weights of linear RGB), count = max(2, ceil(stop - start)). A median of 0 is
/// replaced by 2^-12 L_max (at most 12 stops; a choice where the paper is silent); an all-black
/// reference gives start = stop = 0.
struct ExposureRange {
  double start = 0, stop = 0;
  int count = 2;
  std::vector<double> exposures() const;  ///< evenly spaced, start and stop included
};
ExposureRange exposureRange(const Image& referenceHdr);
}  // namespace flipdetail

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace rtd::eval
