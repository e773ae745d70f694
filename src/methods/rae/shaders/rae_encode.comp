#version 450
// Pass "encode" of the RAE: the network input x = [log1p(max(c, 0) / k), a, n] at the padded
// size (edges replicated: the last row and column repeat), k = clamp(a, 0, 1) + epsilon (1
// without albedo), a = clamp(albedo, 0, 1), n = R n_world (view space). x's planes 3.. are
// also the level-0 features f_0 the first decoder block reads. The twin of the encode loop of
// rae::Network::run and of RaeCpu's view normals (src/methods/rae/).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Color { float color[]; };    // 3 planes, emission taken out
layout(std430, binding = 1) readonly buffer Albedo { float albedo[]; };  // 3 planes (when useAlbedo)
layout(std430, binding = 2) readonly buffer Normal { float normal[]; };  // 3 planes, world space (when useNormal)
layout(std430, binding = 3) writeonly buffer X { float x[]; };           // 3 + features planes, padded size

// r: rows of the rotation part of worldToCamera (world -> view normals), row-major.
layout(push_constant) uniform PC {
  uint width, height, paddedWidth, paddedHeight;
  uint useAlbedo, useNormal;
  float epsilon;
  float r[9];
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.paddedWidth, pc.paddedHeight)) return;
  const uint plane = pc.width * pc.height, i = min(p.y, pc.height - 1u) * pc.width + min(p.x, pc.width - 1u);
  const uint xPlane = pc.paddedWidth * pc.paddedHeight, o = p.y * pc.paddedWidth + p.x;
  uint c = 3u;
  vec3 k = vec3(1.0);
  if (pc.useAlbedo != 0u) {
    const vec3 a = clamp(vec3(albedo[i], albedo[plane + i], albedo[2u * plane + i]), 0.0, 1.0);
    k = a + pc.epsilon;
    for (uint j = 0u; j < 3u; ++j) x[(c++) * xPlane + o] = a[j];
  }
  if (pc.useNormal != 0u) {
    const vec3 n = vec3(normal[i], normal[plane + i], normal[2u * plane + i]);
    for (uint j = 0u; j < 3u; ++j) {
      precise float v = pc.r[j * 3u] * n.x + pc.r[j * 3u + 1u] * n.y + pc.r[j * 3u + 2u] * n.z;
      x[(c++) * xPlane + o] = v;
    }
  }
  for (uint j = 0u; j < 3u; ++j) x[j * xPlane + o] = log1pNonNegative(max(color[j * plane + i], 0.0) / k[j]);
}
