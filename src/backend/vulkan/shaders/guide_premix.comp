#version 450
// Pass "guideRays.premix", second half: Eq. 7 of Voorhuis 2018 on one radiance buffer,
// u'(p) = (u(p) + sum_{q in A(p)} u(q)) / (1 + |A(p)|), A(p) the samples that joined guide p
// (guide_assign.comp). A sample joins a guide of its own 3x3 neighbourhood, so each guide gathers
// from there: samples in the CPU's order (sample index, then scan order), the same sums.
// Interleaved RGB buffers (guide_assign.comp says why).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Guide { float guide[]; };      // 3 per pixel
layout(std430, binding = 1) readonly buffer Samples { float samples[]; };  // 3 per pixel, sample k at k * w * h
layout(std430, binding = 2) readonly buffer Assigned { uint assigned[]; };
layout(std430, binding = 3) writeonly buffer Out { float outp[]; };        // 3 per pixel

layout(push_constant) uniform PC { uint width, height, samples; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, n = pc.width * pc.height;
  vec3 sum = vec3(guide[3 * i], guide[3 * i + 1], guide[3 * i + 2]);
  uint count = 1;
  for (uint k = 0; k < pc.samples; ++k)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = int(p.x) + dx, y = int(p.y) + dy;
        if (x < 0 || y < 0 || x >= int(pc.width) || y >= int(pc.height)) continue;
        const uint s = k * n + uint(y) * pc.width + uint(x);
        if (assigned[s] != i) continue;
        sum += vec3(samples[3 * s], samples[3 * s + 1], samples[3 * s + 2]);
        ++count;
      }
  const float inv = 1.0 / float(count);
  for (uint c = 0; c < 3; ++c) outp[3 * i + c] = sum[c] * inv;
}
