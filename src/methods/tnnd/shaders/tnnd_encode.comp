#version 450
// Pass "encode" of TNND: the 9-channel state [log1p(colour), view-space normal, albedo]
// (Higginson Eq. 2.13). Port of tnnd::encode (src/methods/tnnd/tnnd_model.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Color { float color[]; };    // planes 0-2: radiance
layout(std430, binding = 1) readonly buffer Normal { float normal[]; };  // world space
layout(std430, binding = 2) readonly buffer Albedo { float albedo[]; };
layout(std430, binding = 3) writeonly buffer State { float state[]; };   // 9 planes

// r: rows of the rotation part of worldToCamera (world -> view normals), row-major.
layout(push_constant) uniform PC { uint width, height; float r[9]; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  const vec3 n = vec3(normal[i], normal[plane + i], normal[2u * plane + i]);
  for (uint c = 0; c < 3u; ++c) {
    state[c * plane + i] = log1pNonNegative(max(color[c * plane + i], 0.0));
    precise float v = pc.r[c * 3u] * n.x + pc.r[c * 3u + 1u] * n.y + pc.r[c * 3u + 2u] * n.z;
    state[(3u + c) * plane + i] = v;
    state[(6u + c) * plane + i] = albedo[c * plane + i];
  }
}
