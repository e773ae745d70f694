#version 450
// Gersthofer's composite (Sec. 3.4): (direct + indirect specular) + indirect diffuse, the first
// as the accumulated composite minus the accumulated indirect diffuse, the second after the
// median and the eye exchange. Writes the filter's level-0 source in the accumulator's layout:
// R, G, B, and the composite's moments and length copied. Port of GersthoferEye::back.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer C { float composite[]; };  // accumulator: R, G, B, m1, m2, length
layout(std430, binding = 1) readonly buffer B { float indirect[]; };   // accumulated indirect diffuse
layout(std430, binding = 2) readonly buffer D { float diffuse[]; };    // after median / exchange
layout(std430, binding = 3) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC { uint width, height; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  for (uint c = 0; c < 3; ++c) {
    const uint j = c * plane + i;
    precise float v = max(0.0, composite[j] - indirect[j]) + diffuse[j];
    outp[j] = v;
  }
  for (uint c = 3; c < 6; ++c) outp[c * plane + i] = composite[c * plane + i];
}
