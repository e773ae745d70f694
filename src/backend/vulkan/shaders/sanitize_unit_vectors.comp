#version 450
// Pass "sanitize_unit_vectors": after import, a unit-vector buffer (normal, reflectedNormal,
// mirrorDirection) renormalized in place (sanitize.glsl; twin of renormalizeRow in
// src/core/sanitize.cpp), so no normal weight max(0, n(p).n(q))^sigma_n can exceed 1.
#include "common.glsl"
#include "sanitize.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) buffer Vectors { float v[]; };
layout(std430, binding = 1) buffer Counter { uint replaced[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint counter;  // 3 * the buffer's index
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  vec3 n = vec3(v[i], v[plane + i], v[2 * plane + i]);
  if (!renormalize(n)) return;
  v[i] = n.x;
  v[plane + i] = n.y;
  v[2 * plane + i] = n.z;
  atomicAdd(replaced[pc.counter + kCountRenormalized], 1u);
}
