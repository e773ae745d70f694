// Surface scattering: Lambert diffuse plus GGX microfacet specular in the glTF metallic-roughness
// parameterisation, with a perfect-mirror (delta) limit for roughness below kDeltaRoughness.
#pragma once
#include "render/math.h"

namespace rtd::render {

/// Below this perceptual roughness the specular lobe is a perfect mirror (GGX with alpha < 4e-4
/// is numerically a delta, and the reflection methods need pure-specular pixels).
constexpr float kDeltaRoughness = 0.02f;

inline float schlick(float f0, float cosTheta) {
  const float m = std::clamp(1.0f - cosTheta, 0.0f, 1.0f), m2 = m * m;
  return f0 + (1.0f - f0) * m2 * m2 * m;
}
inline V3 schlick(V3 f0, float cosTheta) {
  const float m = std::clamp(1.0f - cosTheta, 0.0f, 1.0f), m2 = m * m, w = m2 * m2 * m;
  return f0 + (V3(1.0f) - f0) * w;
}

/// The scattering function at one shading point. Values returned are f * cos(theta_i).
struct Bsdf {
  V3 n, t, b;                // shading frame (n faces the outgoing direction)
  V3 base{0.8f};
  float metallic = 0, alpha = 0.25f, specular = 0.5f;
  V3 f0{0.04f};
  float diffuseScale = 1;    // (1 - metallic) * (1 - F_dielectric(cos_o))
  bool deltaSpecular = false;
  bool hasSpecular = true;    // false when F0 = 0 (no specular lobe)
  float pSpecular = 0.5f;    // probability of sampling the specular lobe

  Bsdf(V3 normal, V3 wo, V3 baseColor, float metal, float roughness, float spec);

  /// True when the surface only reflects like a mirror (no diffuse lobe).
  bool pureSpecular() const { return deltaSpecular && diffuseScale <= 0; }

  struct Eval {
    V3 diffuse{0}, specular{0};  // f * cos for each lobe
    float pdf = 0;               // solid-angle pdf of sample() producing wi (non-delta part)
  };
  Eval eval(V3 wo, V3 wi) const;

  struct Sample {
    V3 wi;
    V3 weight{0};      // f * cos / pdf
    float pdf = 0;     // 0 for a delta sample
    bool delta = false;
    bool specular = false;
    bool valid = false;
  };
  Sample sample(V3 wo, float uLobe, float u1, float u2) const;
};

}  // namespace rtd::render
