#version 450
// Pass "export": three planes into the application's RGB or RGBA layout (alpha = 1).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Src { float src[]; };
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint dstOffset, pixelStride, rowStride;  // in 32-bit words
  uint channels;                           // 3 or 4
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint d = pc.dstOffset + p.y * pc.rowStride + p.x * pc.pixelStride;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  for (uint c = 0; c < 3; ++c) dst[d + c] = src[c * plane + i];
  if (pc.channels == 4) dst[d + 3] = 1.0;
}
