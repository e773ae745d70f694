#version 450
// Pass "features" (issue 12, the emitter halo): the a-trous guide's normals with the emitter
// pixels made "no surface", a zero normal, so they weigh 0 as neighbours and take none in the
// a-trous levels and the spatial-variance window. An emitter pixel: the largest channel of
// Buffer::Emission above the threshold. Port of excludeEmitters (src/passes/emitters.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Normal { float normal[]; };
layout(std430, binding = 1) readonly buffer Emission { float emission[]; };
layout(std430, binding = 2) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC {
  uint width, height;
  float threshold;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  const bool emitter = max(emission[i], max(emission[plane + i], emission[2u * plane + i])) > pc.threshold;
  for (uint c = 0; c < 3u; ++c) outp[c * plane + i] = emitter ? 0.0 : normal[c * plane + i];
}
