// Tone mapping and sRGB encoding, written once for every user: the evaluation metrics that work
// on display-referred images (PSNR, SSIM, FLIP, temporal error), the HTML report's pictures,
// and any denoiser pass that needs a display-referred value. Header-only (inline scalar
// functions) so both librtdenoise and librtdenoise_eval use the same code without exporting it.
// Constants and their sources: docs/evaluation.md, "Tone mapping".
#pragma once
#include <algorithm>
#include <cmath>

namespace rtd::tonemap {

enum class Operator { Clamp, Reinhard, Aces };

/// sRGB opto-electronic transfer function (IEC 61966-2-1): linear [0,1] -> encoded [0,1].
inline float srgbEncode(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

/// Inverse of srgbEncode: encoded [0,1] -> linear [0,1].
inline float srgbDecode(float encoded) {
  const float c = std::clamp(encoded, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// Filmic curve fitted to the ACES reference rendering transform by Narkowicz (2015),
/// "ACES Filmic Tone Mapping Curve": x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clamped.
inline float acesNarkowicz(float x) {
  x = std::max(x, 0.0f);
  return std::clamp(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

/// Linear HDR radiance (one channel) -> display-linear [0,1] with the chosen curve, after
/// multiplying by `scale` (= 2^exposure). Per channel, so hue shifts at saturation as in
/// most real-time renderers.
inline float toneMapChannel(float linear, Operator op, float scale) {
  const float x = std::isfinite(linear) ? std::max(linear, 0.0f) * scale : 0.0f;
  switch (op) {
    case Operator::Clamp: return std::min(x, 1.0f);
    case Operator::Reinhard: return x / (1.0f + x);  // Reinhard et al. 2002, eq. 3
    case Operator::Aces: default: return acesNarkowicz(x);
  }
}

/// Linear HDR -> sRGB-encoded display value in [0,1].
inline float toneMapToSrgb(float linear, Operator op, float scale) {
  return srgbEncode(toneMapChannel(linear, op, scale));
}

/// Invertible display encoding of the TAA's display domain (rtd/methods/taa.h): Reinhard
/// x/(1+x) (Reinhard et al. 2002, eq. 3) then gamma 2 (a square root: the gamma-2.2 encoding of
/// the papers within a few percent, at the cost of one sqrt). Negative and NaN give 0, +inf 1.
inline float taaEncode(float x) {
  x = x > 0.0f ? std::min(x, 1e30f) : 0.0f;
  return std::sqrt(x / (1.0f + x));
}
/// Largest encoded value taaDecode accepts: 1 - 2^-21, which decodes to 2^20 - 1 (about 1e6,
/// the brightest radiance the display-domain TAA returns; float resolves the encoding near 1
/// to 2^-24, so radiance x comes back to about x * 2^-23 * (1 + x) relative precision).
constexpr float kTaaMaxEncoded = 1.0f - 1.0f / 2097152.0f;
/// Inverse of taaEncode: t = y^2, x = t / (1 - t).
inline float taaDecode(float y) {
  y = std::clamp(y, 0.0f, kTaaMaxEncoded);
  const float t = y * y;
  return t / (1.0f - t);
}

/// Relative luminance of linear Rec.709/sRGB primaries (ITU-R BT.709 weights). Applied to
/// sRGB-encoded values it gives luma, which is what the temporal error uses (see docs).
inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

}  // namespace rtd::tonemap
