#version 450
// Pass "guideRays.resolve": the post-filter copy of Voorhuis 2018 Sec. 5 (GuideRays::resolve in
// src/passes/guide_rays.cpp): each non-guide sample takes the filtered colour of the guide it
// joined (guide_assign.comp), each pixel is the mean of its guide's and its samples' colours.
// Interleaved RGB buffers (the denoiser's export into a VulkanBufferView).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Filtered { float filtered[]; };  // 3 per pixel
layout(std430, binding = 1) readonly buffer Assigned { uint assigned[]; };   // sample k at k * w * h
layout(std430, binding = 2) writeonly buffer Out { float outp[]; };          // 3 per pixel

layout(push_constant) uniform PC { uint width, height, samples; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, n = pc.width * pc.height;
  vec3 sum = vec3(filtered[3 * i], filtered[3 * i + 1], filtered[3 * i + 2]);
  for (uint k = 0; k < pc.samples; ++k) {
    const uint g = assigned[k * n + i];
    sum += vec3(filtered[3 * g], filtered[3 * g + 1], filtered[3 * g + 2]);
  }
  const float inv = 1.0 / float(pc.samples + 1);
  for (uint c = 0; c < 3; ++c) outp[3 * i + c] = sum[c] * inv;
}
