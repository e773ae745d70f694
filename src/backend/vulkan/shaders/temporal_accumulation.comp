#version 450
// Pass "accumulate": history length, colour and the luminance moments (Schied et al. 2017
// Sec. 4.1, 4.2) with the new-sample weight w = max(1/n, alpha) (Koskela et al. 2019 Sec. 4.1).
// History and output hold 6 planes: colour R, G, B, moment 1, moment 2, history length; with
// option 8 (no moments, BMFR: TemporalAccumulator::resize(w, h, false)) 4: R, G, B, length.
// Port of TemporalAccumulator::run (src/passes/temporal_accumulation.cpp).
// Variant temporal_accumulation_masked (RTD_SAMPLE_MASK, AccumulationOptions::sampleMask):
// progressive rendering below 1 spp (Dundr Sec. 5) with the frame's sample mask at binding 4.
// Variant temporal_accumulation_gradient (RTD_TEMPORAL_GRADIENT, AccumulationOptions::
// temporalGradient): A-SVGF's adaptive history with the per-stratum gradient at binding 4.
// variant: temporal_accumulation_masked RTD_SAMPLE_MASK
// variant: temporal_accumulation_gradient RTD_TEMPORAL_GRADIENT
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Rp { uint rp[]; };
layout(std430, binding = 1) readonly buffer Color { float color[]; };
layout(std430, binding = 2) readonly buffer Hist { float hist[]; };
layout(std430, binding = 3) writeonly buffer Out { float outp[]; };
#ifdef RTD_SAMPLE_MASK
layout(std430, binding = 4) readonly buffer Mask { float sampleMask[]; };
#endif
#ifdef RTD_TEMPORAL_GRADIENT
layout(std430, binding = 4) readonly buffer Gradient { float temporalGradient[]; };  // first plane: G
#endif
// Voorhuis 2018 (AccumulationOptions::alphaPlane, clipLow / clipHigh): a per-pixel colour blend
// floor, and a box (low RGB, high RGB) the reprojected colour history is clamped to before
// the blend (neighbourhood clipping, Sec. 4.2.3). Bound to a dummy when not used.
layout(std430, binding = 5) readonly buffer Alpha { float alphaPlane[]; };
layout(std430, binding = 6) readonly buffer Clip { float clipBox[]; };

float histAt(uint j) { return hist[j]; }
#define RP_GATHER
#include "reprojection.glsl"

layout(push_constant) uniform PC {
  uint width, height;
  float alpha, momentsAlpha;
  float maxHistoryLength;
  uint luminanceMode;      // MomentLuminance: 0 Rec709, 1 Rec601, 2 CIE L*
  uint cumulativeMoments;  // 1: moments w = max(1/n, alpha); 0: plain EMA (Schied)
  uint gradientWidth, gradientStride;  // temporal_accumulation_gradient: texels per row, pixels per texel
  float historyExponent;
  uint options;  // 1: per-pixel alpha (binding 5); 2: clip the colour history (binding 6); 4: fixed weights; 8: no moments
} pc;

float colourHistory(uint i, uint k, uint w, uint plane) {
  float h = gatherPlane(i, k * plane, w, plane);
  if ((pc.options & 2u) != 0u) h = min(max(h, clipBox[k * plane + i]), clipBox[(3u + k) * plane + i]);
  return h;
}

#ifdef RTD_TEMPORAL_GRADIENT
// (1 - G)^e as historyShrink() on the CPU: integral exponents by repeated squaring.
float historyShrink(float g, float e) {
  const float b = 1.0 - g;
  if (e == floor(e) && e >= 0.0 && e <= 64.0) {
    float r = 1.0, d = b;
    for (int k = int(e); k != 0; k >>= 1) {
      if ((k & 1) != 0) r *= d;
      d *= d;
    }
    return r;
  }
  return pow(b, e);
}
#endif

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint w = pc.width, plane = pc.width * pc.height;
  const uint i = p.y * w + p.x;
  const bool none = rpKind(i) == RP_NONE;
  const bool moments = (pc.options & 8u) == 0u;
  const uint lengthPlane = moments ? 5u : 3u;

  // BMFR rounds the reprojected length to an integer (8-bit counts); std::round semantics.
  // Disoccluded pixels: n = 1, weight 1. Port of the fused TemporalAccumulator::run.
#ifdef RTD_SAMPLE_MASK
  if (sampleMask[i] == 0.0) {
    // No sample this frame: the history carries over unchanged (length rounded as below);
    // without history the pixel stays missing (length 0).
    for (uint k = 0; k < lengthPlane; ++k)
      outp[k * plane + i] = none ? 0.0 : (k < 3u ? colourHistory(i, k, w, plane) : gatherPlane(i, k * plane, w, plane));
    outp[lengthPlane * plane + i] = none ? 0.0 : floor(gatherPlane(i, lengthPlane * plane, w, plane) + 0.5);
    return;
  }
#endif
#ifdef RTD_TEMPORAL_GRADIENT
  // A-SVGF (AccumulationOptions::temporalGradient): N' = min(N (1-G)^e + 1, cap), unrounded;
  // weights mix(max(1/N', floor), 1, G).
  const float g = clamp(temporalGradient[(p.y / pc.gradientStride) * pc.gradientWidth + p.x / pc.gradientStride], 0.0, 1.0);
  const float histLength = none ? 0.0 : gatherPlane(i, 5u * plane, w, plane);
  precise float n = min(histLength * historyShrink(g, pc.historyExponent) + 1.0, pc.maxHistoryLength);
  const float a0 = max(1.0 / n, pc.alpha), am0 = max(1.0 / n, pc.momentsAlpha);
  precise float a = a0 + (1.0 - a0) * g;
  precise float am = am0 + (1.0 - am0) * g;
#else
  const float n = none ? 1.0 : min(floor(gatherPlane(i, lengthPlane * plane, w, plane) + 0.5) + 1.0, pc.maxHistoryLength);
  // Fixed weights (options 4, Gersthofer Sec. 3.4.1): alpha wherever there is history.
  const bool fixedWeights = (pc.options & 4u) != 0u;
  const float floorAlpha = (pc.options & 1u) != 0u ? alphaPlane[i] : pc.alpha;
  const float a = fixedWeights ? (n <= 1.0 ? 1.0 : floorAlpha) : max(1.0 / n, floorAlpha);
  const float am = fixedWeights ? (n <= 1.0 ? 1.0 : pc.momentsAlpha)
                                : pc.cumulativeMoments != 0u ? max(1.0 / n, pc.momentsAlpha) : (none ? 1.0 : pc.momentsAlpha);
#endif
  outp[lengthPlane * plane + i] = n;

  const vec3 c = vec3(color[i], color[plane + i], color[2u * plane + i]);
  const float l = momentLuminance(pc.luminanceMode, c);
  for (uint k = 0; k < 3; ++k) {
    const float hist = none ? 0.0 : colourHistory(i, k, w, plane);
    precise float v = a * c[k] + (1.0 - a) * hist;
    outp[k * plane + i] = v;
  }
  if (!moments) return;
  const float h1 = none ? 0.0 : gatherPlane(i, 3u * plane, w, plane);
  const float h2 = none ? 0.0 : gatherPlane(i, 4u * plane, w, plane);
  precise float m1 = am * l + (1.0 - am) * h1;
  precise float m2 = am * l * l + (1.0 - am) * h2;
  outp[3u * plane + i] = m1;
  outp[4u * plane + i] = m2;
}
