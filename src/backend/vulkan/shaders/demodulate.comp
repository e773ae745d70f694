#version 450
// Pass "demodulate": radiance / albedo' per channel (Schied et al. 2017 Sec. 4), albedo' = 1
// where the albedo is below 1e-3 (black or emissive surfaces keep their radiance).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Color { float color[]; };
layout(std430, binding = 1) readonly buffer Albedo { float albedo[]; };
layout(std430, binding = 2) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC { uint width, height, hasAlbedo; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  for (uint c = 0; c < 3; ++c) {
    const uint k = c * plane + i;
    float v = color[k];
    if (pc.hasAlbedo != 0) {
      const float a = albedo[k];
      v /= a > 1e-3 ? a : 1.0;
    }
    outp[k] = v;
  }
}
