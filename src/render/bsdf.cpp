// GGX (Trowbridge-Reitz) specular with height-correlated Smith masking (Heitz 2014) and visible-
// normal sampling (Heitz 2018), plus a Lambert lobe weighted by (1 - metallic)(1 - F).
#include "render/bsdf.h"

namespace rtd::render {

namespace {

float ggxD(float cosH, float a2) {
  const float d = cosH * cosH * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}
float smithSqrt(float c, float a2) { return std::sqrt(a2 + (1.0f - a2) * c * c); }
float smithG1(float c, float a2) { return 2.0f * c / (c + smithSqrt(c, a2)); }
float smithG2(float co, float ci, float a2) { return 2.0f * co * ci / (ci * smithSqrt(co, a2) + co * smithSqrt(ci, a2)); }

/// Heitz 2018, "Sampling the GGX Distribution of Visible Normals": wo in the local frame (z = n).
V3 sampleVisibleNormal(V3 wo, float alpha, float u1, float u2) {
  const V3 vh = normalize({alpha * wo.x, alpha * wo.y, wo.z});
  const float lensq = vh.x * vh.x + vh.y * vh.y;
  const V3 t1 = lensq > 0 ? V3(-vh.y, vh.x, 0) / std::sqrt(lensq) : V3(1, 0, 0);
  const V3 t2 = cross(vh, t1);
  const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
  const float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  const float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  const V3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return normalize({alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)});
}

}  // namespace

Bsdf::Bsdf(V3 normal, V3 wo, V3 baseColor, float metal, float roughness, float spec)
    : n(normal), base(baseColor), metallic(metal), specular(spec) {
  basis(n, t, b);
  const float r = std::max(roughness, 0.0f);
  deltaSpecular = r < kDeltaRoughness;
  alpha = std::max(r * r, 1e-4f);
  f0 = lerp(V3(0.08f * specular), base, metallic);
  const float cosO = std::max(0.0f, dot(n, wo));
  // F0 = 0 means no specular lobe at all (Schlick's grazing term would otherwise add one), so
  // `specular: 0` gives an exactly Lambertian surface.
  hasSpecular = maxComponent(f0) > 0;
  diffuseScale = (1.0f - metallic) * (specular > 0 ? 1.0f - schlick(0.08f * specular, cosO) : 1.0f);
  // Choose lobes by their approximate reflectance at this view angle (one-sample MIS over lobes).
  const float ws = hasSpecular ? luminance(schlick(f0, cosO)) : 0.0f, wd = diffuseScale * luminance(base);
  if (ws <= 0) pSpecular = 0;
  else if (wd <= 0) pSpecular = 1;
  else pSpecular = std::clamp(ws / (ws + wd), 0.1f, 0.9f);
}

Bsdf::Eval Bsdf::eval(V3 wo, V3 wi) const {
  Eval e;
  const float ci = dot(n, wi), co = dot(n, wo);
  if (ci <= 0 || co <= 0) return e;
  if (pSpecular < 1) {
    e.diffuse = base * (diffuseScale * kInvPi * ci);
    e.pdf += (1.0f - pSpecular) * ci * kInvPi;
  }
  if (!deltaSpecular && pSpecular > 0) {
    const V3 h = normalize(wo + wi);
    const float ch = std::max(0.0f, dot(n, h)), a2 = alpha * alpha;
    const float d = ggxD(ch, a2);
    const V3 f = schlick(f0, std::max(0.0f, dot(wo, h)));
    e.specular = f * (d * smithG2(co, ci, a2) / (4.0f * co));
    e.pdf += pSpecular * d * smithG1(co, a2) / (4.0f * co);
  }
  return e;
}

Bsdf::Sample Bsdf::sample(V3 wo, float uLobe, float u1, float u2) const {
  Sample s;
  const float co = dot(n, wo);
  if (co <= 0) return s;
  if (uLobe < pSpecular) {
    s.specular = true;
    if (deltaSpecular) {
      s.wi = reflect(-wo, n);
      s.delta = true;
      s.weight = schlick(f0, co) / pSpecular;
      s.valid = true;
      return s;
    }
    const V3 woL{dot(wo, t), dot(wo, b), co};
    const V3 h = sampleVisibleNormal(woL, alpha, u1, u2);
    const V3 hw = t * h.x + b * h.y + n * h.z;
    s.wi = reflect(-wo, hw);
  } else {
    // Cosine-weighted hemisphere (Malley's method).
    const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
    const float x = r * std::cos(phi), y = r * std::sin(phi), z = std::sqrt(std::max(0.0f, 1.0f - u1));
    s.wi = t * x + b * y + n * z;
  }
  const Eval e = eval(wo, s.wi);
  if (e.pdf <= 0) return s;
  s.pdf = e.pdf;
  s.weight = (e.diffuse + e.specular) / e.pdf;
  s.valid = maxComponent(s.weight) > 0;
  return s;
}

}  // namespace rtd::render
