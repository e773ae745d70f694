#version 450
// Pass "median": 3x3 per-channel median (Voorhuis Sec. 6, fireflies) of diffuse pixels
// (roughness >= 0.9, or every pixel without a roughness buffer); others are copied, edges
// clamped. Port of svgf::median3x3. Also Gersthofer's median of indirect diffuse (Sec. 3.4.2).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float src[]; };
layout(std430, binding = 1) readonly buffer Rough { float roughness[]; };
layout(std430, binding = 2) writeonly buffer Out { float dst[]; };
// Gersthofer (skipWhenMasked): counts of gersthofer_coverage; where fewer pixels were sampled
// than are visible (masking is on) the median is off and the input is copied.
layout(std430, binding = 3) readonly buffer Counter { uint counter[]; };

layout(push_constant) uniform PC { uint width, height, hasRoughness, skipWhenMasked; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  const bool masked = pc.skipWhenMasked != 0u && counter[0] < counter[1];
  const bool keep = masked || (pc.hasRoughness != 0u && roughness[i] < 0.9);
  for (uint c = 0; c < 3; ++c) {
    if (keep) {
      dst[c * plane + i] = src[c * plane + i];
      continue;
    }
    float v[9];
    int k = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = clamp(int(p.x) + dx, 0, int(pc.width) - 1), y = clamp(int(p.y) + dy, 0, int(pc.height) - 1);
        v[k++] = src[c * plane + uint(y) * pc.width + uint(x)];
      }
    // Partial selection sort up to the middle element.
    for (int a = 0; a <= 4; ++a)
      for (int b = a + 1; b < 9; ++b)
        if (v[b] < v[a]) { const float t = v[a]; v[a] = v[b]; v[b] = t; }
    dst[c * plane + i] = v[4];
  }
}
