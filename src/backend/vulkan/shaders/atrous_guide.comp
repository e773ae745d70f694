#version 450
// Pass "features": the screen-space depth gradient the a-trous depth weight needs (Schied et al.
// 2017 Eq. 3): Buffer::DepthGradient when given, else the smaller one-sided difference per axis
// (so a silhouette next to a pixel does not widen its tolerance); made huge where
// |grad z| > maxDepthSlope * z (Dundr Sec. 4.4.2), which turns w_z off. Port of AtrousGuide::build.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Depth { float depth[]; };
layout(std430, binding = 1) readonly buffer Grad { float grad[]; };
layout(std430, binding = 2) writeonly buffer Out { float outp[]; };  // gradX, gradY

layout(push_constant) uniform PC { uint width, height, hasGradient; float maxDepthSlope; } pc;

float smaller(float a, float b) { return abs(a) < abs(b) ? a : b; }

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const int w = int(pc.width), h = int(pc.height), x = int(p.x), y = int(p.y);
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  const float z = depth[i];
  float gx, gy;
  if (pc.hasGradient != 0u) {
    gx = grad[i];
    gy = grad[plane + i];
  } else {
    const uint row = uint(y * w);
    const float left = x > 0 ? z - depth[row + uint(x - 1)] : depth[row + uint(x + (w > 1 ? 1 : 0))] - z;
    const float right = x + 1 < w ? depth[row + uint(x + 1)] - z : left;
    gx = smaller(left, right);
    const float up = depth[uint(max(y - 1, 0) * w + x)], dn = depth[uint(min(y + 1, h - 1) * w + x)];
    const float dUp = y > 0 ? z - up : dn - z;
    const float dDown = y + 1 < h ? dn - z : dUp;
    gy = smaller(dUp, dDown);
  }
  if (pc.maxDepthSlope > 0.0 && max(abs(gx), abs(gy)) > pc.maxDepthSlope * abs(z)) {
    // As AtrousGuide::build: |gx ox + gy oy| > 5e7 for any non-zero offset within 64 pixels.
    gx = 4294967296.0;  // 2^32
    gy = 4294967296.0 * 0.41421356;
  }
  outp[i] = gx;
  outp[plane + i] = gy;
}
