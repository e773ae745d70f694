#version 450
// 3x3 Gaussian (1/16, 1/8, 1/4) of one plane, clamped to edge: SVGF's g3x3 of the variance when
// run once before the first level (Dundr Sec. 4.3). Port of gaussian3x3 (src/passes/atrous.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float src[]; };
layout(std430, binding = 1) writeonly buffer Out { float dst[]; };

layout(push_constant) uniform PC { uint width, height, srcPlane, dstPlane; } pc;

float at(int x, int y) {
  x = clamp(x, 0, int(pc.width) - 1);
  y = clamp(y, 0, int(pc.height) - 1);
  return src[pc.srcPlane * pc.width * pc.height + uint(y) * pc.width + uint(x)];
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const int x = int(p.x), y = int(p.y);
  const float v = 0.0625 * (at(x - 1, y - 1) + at(x + 1, y - 1) + at(x - 1, y + 1) + at(x + 1, y + 1)) +
                  0.125 * (at(x, y - 1) + at(x, y + 1) + at(x - 1, y) + at(x + 1, y)) + 0.25 * at(x, y);
  dst[pc.dstPlane * pc.width * pc.height + p.y * pc.width + p.x] = v;
}
