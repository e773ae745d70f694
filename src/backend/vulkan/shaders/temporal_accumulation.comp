#version 450
// Pass "accumulate": history length, colour and the luminance moments (Schied et al. 2017
// Sec. 4.1, 4.2) with the new-sample weight w = max(1/n, alpha) (Koskela et al. 2019 Sec. 4.1).
// History and output hold 6 planes: colour R, G, B, moment 1, moment 2, history length.
// Port of TemporalAccumulator::run (src/passes/temporal_accumulation.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Rp { uint rp[]; };
layout(std430, binding = 1) readonly buffer Color { float color[]; };
layout(std430, binding = 2) readonly buffer Hist { float hist[]; };
layout(std430, binding = 3) writeonly buffer Out { float outp[]; };

float histAt(uint j) { return hist[j]; }
#define RP_GATHER
#include "reprojection.glsl"

layout(push_constant) uniform PC {
  uint width, height;
  float alpha, momentsAlpha;
  float maxHistoryLength;
  uint luminanceMode;      // MomentLuminance: 0 Rec709, 1 Rec601, 2 CIE L*
  uint cumulativeMoments;  // 1: moments w = max(1/n, alpha); 0: plain EMA (Schied)
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint w = pc.width, plane = pc.width * pc.height;
  const uint i = p.y * w + p.x;
  const bool none = rpKind(i) == RP_NONE;

  // BMFR rounds the reprojected length to an integer (8-bit counts); std::round semantics.
  const float n = none ? 0.0 : floor(gatherPlane(i, 5u * plane, w, plane) + 0.5);
  const float len = min(n + 1.0, pc.maxHistoryLength);
  outp[5u * plane + i] = len;

  const vec3 c = vec3(color[i], color[plane + i], color[2u * plane + i]);
  const float l = momentLuminance(pc.luminanceMode, c);
  precise float l2 = l * l;
  const float cur[5] = float[5](c.r, c.g, c.b, l, l2);
  for (uint k = 0; k < 5; ++k) {
    if (none) {
      outp[k * plane + i] = cur[k];
      continue;
    }
    const float a = k < 3u ? max(1.0 / len, pc.alpha)
                           : (pc.cumulativeMoments != 0u ? max(1.0 / len, pc.momentsAlpha) : pc.momentsAlpha);
    precise float v = a * cur[k] + (1.0 - a) * gatherPlane(i, k * plane, w, plane);
    outp[k * plane + i] = v;
  }
}
