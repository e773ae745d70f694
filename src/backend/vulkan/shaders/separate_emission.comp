#version 450
// Pass "separate_emission": radiance minus the primary hit's emission (Buffer::Emission), clamped
// at 0, so methods filter only the noisy part; export adds the emission back (as on the CPU).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) buffer Radiance { float radiance[]; };
layout(std430, binding = 1) readonly buffer Emission { float emission[]; };

layout(push_constant) uniform PC {
  uint width, height;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  for (uint c = 0; c < 3; ++c) radiance[c * plane + i] = max(0.0, radiance[c * plane + i] - emission[c * plane + i]);
}
