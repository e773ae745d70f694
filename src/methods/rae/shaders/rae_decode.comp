#version 450
// Pass "decode" of the RAE: radiance = expm1(clamp(y, 0, maxOutput)) k of the network output y
// (3 planes at the padded size), cropped to the frame; k = clamp(albedo, 0, 1) + epsilon (1
// without albedo). The twin of the decode loop of rae::Network::run.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Y { float y[]; };            // 3 planes, padded size
layout(std430, binding = 1) readonly buffer Albedo { float albedo[]; };  // 3 planes (when useAlbedo)
layout(std430, binding = 2) writeonly buffer Out { float outp[]; };      // 3 planes, frame size

layout(push_constant) uniform PC {
  uint width, height, paddedWidth, paddedHeight, useAlbedo;
  float epsilon, maxOutput;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  const uint yPlane = pc.paddedWidth * pc.paddedHeight, j = p.y * pc.paddedWidth + p.x;
  for (uint c = 0u; c < 3u; ++c) {
    const float k = pc.useAlbedo != 0u ? clamp(albedo[c * plane + i], 0.0, 1.0) + pc.epsilon : 1.0;
    outp[c * plane + i] = expm1NonNegative(clamp(y[c * yPlane + j], 0.0, pc.maxOutput)) * k;
  }
}
