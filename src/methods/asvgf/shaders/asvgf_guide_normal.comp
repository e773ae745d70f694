#version 450
// Pass "features" of asvgf with reflectedNormals (thesis Sec. 1.2.1, Fig. 3.6): the filter's
// normal is the reflected hit's where reflectedNormal is non-zero (mirror pixels), else the
// primary hit's. Port of asvgf::guideNormals.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Normal { float normal[]; };
layout(std430, binding = 1) readonly buffer Reflected { float reflected[]; };
layout(std430, binding = 2) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC {
  uint width, height;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  const vec3 r = vec3(reflected[i], reflected[plane + i], reflected[2u * plane + i]);
  const bool useReflected = r.x != 0.0 || r.y != 0.0 || r.z != 0.0;
  for (uint c = 0u; c < 3u; ++c) outp[c * plane + i] = useReflected ? reflected[c * plane + i] : normal[c * plane + i];
}
