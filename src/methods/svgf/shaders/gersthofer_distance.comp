#version 450
// Gersthofer Sec. 3.4.1: the indirect ray length z_i (Buffer::SecondaryDistance) accumulated
// with the colour's weights and taps (fixed alpha, or max(1/n, alpha)); unsampled pixels keep
// their history. Port of GersthoferEye::accumulateDistance.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Rp { uint rp[]; };
layout(std430, binding = 1) readonly buffer Cur { float current[]; };
layout(std430, binding = 2) readonly buffer Hist { float hist[]; };
layout(std430, binding = 3) readonly buffer Acc { float acc[]; };  // this frame's accumulator: n is plane 5
layout(std430, binding = 4) readonly buffer Mask { float sampleMask[]; };
layout(std430, binding = 5) writeonly buffer Out { float outp[]; };

float histAt(uint j) { return hist[j]; }
#define RP_GATHER
#include "reprojection.glsl"

layout(push_constant) uniform PC { uint width, height; float alpha; uint fixedAlpha, hasHistory, hasMask; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint w = pc.width, plane = w * pc.height, i = p.y * w + p.x;
  const float h = pc.hasHistory != 0u ? gatherPlane(i, 0u, w, plane) : 0.0;
  if (pc.hasMask != 0u && sampleMask[i] == 0.0) {
    outp[i] = h;
    return;
  }
  const float n = pc.hasHistory != 0u ? acc[5u * plane + i] : 1.0;
  const float a = pc.fixedAlpha != 0u ? (n <= 1.0 ? 1.0 : pc.alpha) : max(1.0 / n, pc.alpha);
  precise float v = a * current[i] + (1.0 - a) * h;
  outp[i] = v;
}
