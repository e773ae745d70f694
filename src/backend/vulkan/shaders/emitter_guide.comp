#version 450
// Pass "features" (issue 12, the emitter halo): the a-trous guide's normals with the emitter
// pixels made "no surface", a zero normal, so they weigh 0 as neighbours and take none in the
// a-trous levels and the spatial-variance window. An emitter pixel: the largest channel of
// Buffer::Emission above the threshold; with albedoTest (excludeEmitters off) only those whose
// albedo is no reflectance (a channel above 1: Cycles' pure emitters). Port of excludeEmitters
// (src/passes/emitters.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Normal { float normal[]; };
layout(std430, binding = 1) readonly buffer Emission { float emission[]; };
layout(std430, binding = 2) readonly buffer Albedo { float albedo[]; };
layout(std430, binding = 3) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC {
  uint width, height;
  float threshold;
  uint albedoTest;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  bool emitter = max(emission[i], max(emission[plane + i], emission[2u * plane + i])) > pc.threshold;
  if (emitter && pc.albedoTest != 0u) emitter = max(albedo[i], max(albedo[plane + i], albedo[2u * plane + i])) > 1.0;
  for (uint c = 0; c < 3u; ++c) outp[c * plane + i] = emitter ? 0.0 : normal[c * plane + i];
}
