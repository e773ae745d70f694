#version 450
// Pass "conventions": one imported buffer's planes converted in place from the engine's
// conventions to the native ones (rtd::FrameConventions). The numbers come from
// ConventionTransform (src/core/conventions.h), and the arithmetic is applyConventions()'s.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) buffer Planes { float v[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint mode;  // 0: motion (2 planes), 1: normal (3 planes), 2: hardware depth (1 plane)
  // motion: scale x, y, offset x, y; normal: 3x3 row-major; depth: ndcScale, ndcOffset, p22, p23, p32, p33
  float a[9];
} pc;

const float kFarDepth = 1e30;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  if (pc.mode == 0u) {
    for (uint c = 0; c < 2; ++c) {
      precise float m = v[c * plane + i] * pc.a[c] + pc.a[2 + c];
      v[c * plane + i] = m;
    }
  } else if (pc.mode == 1u) {
    const vec3 n = vec3(v[i], v[plane + i], v[2 * plane + i]);
    precise vec3 w;
    for (uint r = 0; r < 3; ++r) w[r] = pc.a[3 * r] * n.x + pc.a[3 * r + 1] * n.y + pc.a[3 * r + 2] * n.z;
    precise float len2 = w.x * w.x + w.y * w.y + w.z * w.z;
    const float s = len2 > 0.0 ? 1.0 / sqrt(len2) : 0.0;  // background (zero) normals stay zero
    for (uint r = 0; r < 3; ++r) v[r * plane + i] = w[r] * s;
  } else {
    precise float ndc = v[i] * pc.a[0] + pc.a[1];
    precise float z = abs((pc.a[3] - pc.a[5] * ndc) / (pc.a[4] * ndc - pc.a[2]));
    v[i] = z < kFarDepth ? z : kFarDepth;  // also infinity and 0/0
  }
}
