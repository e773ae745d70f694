#version 450
// Pass "decode" of TNND: radiance = expm1(max(s_c, 0)) of the state's first three channels.
// Port of tnnd::decode (src/methods/tnnd/tnnd_model.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer State { float state[]; };
layout(std430, binding = 1) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC { uint width, height; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  for (uint c = 0; c < 3u; ++c) {
    outp[c * plane + i] = expm1NonNegative(max(state[c * plane + i], 0.0));
  }
}
