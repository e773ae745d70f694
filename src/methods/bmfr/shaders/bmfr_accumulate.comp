#version 450
// Pass "accumulateFiltered" of BMFR (Koskela et al. 2019 Sec. 4.3): the fitted colour
// accumulated again with phase I's reprojection taps and sample counts, w = max(1/n, alpha).
// Port of accumulateRow (src/passes/temporal_accumulation.cpp), every row at once.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Rp { uint rp[]; };
layout(std430, binding = 1) readonly buffer Noisy { float noisy[]; };  // phase I: R, G, B, n (no moment planes)
layout(std430, binding = 2) readonly buffer Current { float current[]; };
layout(std430, binding = 3) readonly buffer Hist { float hist[]; };
layout(std430, binding = 4) writeonly buffer Out { float outp[]; };

float histAt(uint j) { return hist[j]; }
#define RP_GATHER
#include "reprojection.glsl"

layout(push_constant) uniform PC {
  uint width, height;
  float alpha;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint w = pc.width, plane = pc.width * pc.height, i = p.y * w + p.x;
  if (rpKind(i) == RP_NONE) {
    for (uint c = 0; c < 3u; ++c) outp[c * plane + i] = current[c * plane + i];
    return;
  }
  const float a = max(1.0 / noisy[3u * plane + i], pc.alpha);
  for (uint c = 0; c < 3u; ++c) {
    precise float v = a * current[c * plane + i] + (1.0 - a) * gatherPlane(i, c * plane, w, plane);
    outp[c * plane + i] = v;
  }
}
