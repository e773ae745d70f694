#version 450
// Gersthofer's post-processing input (Sec. 3.5): the remodulated image plus the separated
// emission (the emitters belong to the final image), and FXAA's luma of it as plane 3 (the
// fxaa pass reads R, G, B, luma). Port of the first step of GersthoferEye::back's post-processing.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float src[]; };
layout(std430, binding = 1) readonly buffer Emission { float emission[]; };
layout(std430, binding = 2) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC { uint width, height, hasEmission; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  vec3 c;
  for (uint k = 0; k < 3; ++k) {
    precise float v = src[k * plane + i] + (pc.hasEmission != 0u ? emission[k * plane + i] : 0.0);
    c[k] = v;
    outp[k * plane + i] = v;
  }
  outp[3u * plane + i] = fxaaLuma(c);
}
