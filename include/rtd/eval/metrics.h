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
  double pixelsPerDegree() const;
};

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
  FlipReference(const Image& reference, const FlipSettings& settings = {});
  /// Same as flip(test, reference, settings, errorMap).
  double compare(const Image& test, Image* errorMap = nullptr) const;
  bool empty() const { return !prepared_; }
  struct Prepared;

 private:
  std::shared_ptr<const Prepared> prepared_;
  FlipSettings settings_;
  int width_ = 0, height_ = 0;
};

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
}  // namespace flipdetail

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace rtd::eval
