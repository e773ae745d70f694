#version 450
// Pass "reflections" (guide gradient): the frame's depth gradient, except at mirror pixels
// (class 3), whose guide depth is the virtual image's: there the smaller one-sided difference
// of that depth per axis (as svgf::Reflections::prepare; atrous_guide then applies
// maxDepthSlope to the result).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Cls { float cls[]; };
layout(std430, binding = 1) readonly buffer GuideDepth { float zv[]; };
layout(std430, binding = 2) readonly buffer Grad { float grad[]; };
layout(std430, binding = 3) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC { uint width, height; } pc;

float smaller(float a, float b) { return abs(a) < abs(b) ? a : b; }

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const int w = int(pc.width), h = int(pc.height), x = int(p.x), y = int(p.y);
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  if (cls[i] != 3.0) {
    outp[i] = grad[i];
    outp[n + i] = grad[n + i];
    return;
  }
  const float z = zv[i];
  const float left = x > 0 ? z - zv[i - 1u] : (w > 1 ? zv[i + 1u] - z : 0.0);
  const float right = x + 1 < w ? zv[i + 1u] - z : left;
  const float up = y > 0 ? z - zv[i - pc.width] : (h > 1 ? zv[i + pc.width] - z : 0.0);
  const float down = y + 1 < h ? zv[i + pc.width] - z : up;
  outp[i] = smaller(left, right);
  outp[n + i] = smaller(up, down);
}
