#version 450
// Gersthofer's composite (Sec. 3.4): (direct + indirect specular) + indirect diffuse, the first
// as the accumulated composite minus the accumulated indirect diffuse, the second after the
// median and the eye exchange (F_SPLIT; else the accumulated composite as it is), times Eq.
// 3.1's factor (F_BOOST; the current sample, binding 5, takes it too). Writes the filter's
// level-0 source in the accumulator's layout:
// R, G, B, and the composite's moments and length copied. Port of GersthoferEye::back.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer C { float composite[]; };  // accumulator: R, G, B, m1, m2, length
layout(std430, binding = 1) readonly buffer B { float indirect[]; };   // accumulated indirect diffuse
layout(std430, binding = 2) readonly buffer D { float diffuse[]; };    // after median / exchange
layout(std430, binding = 3) readonly buffer Factor { float factor[]; };  // gersthofer_boost
layout(std430, binding = 4) writeonly buffer Out { float outp[]; };
layout(std430, binding = 5) buffer Cur { float current[]; };  // this frame's sample: boosted alike (spatial variance)

#define F_SPLIT 1u
#define F_BOOST 2u

layout(push_constant) uniform PC { uint width, height, flags; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  const float k = (pc.flags & F_BOOST) != 0u ? factor[i] : 1.0;
  for (uint c = 0; c < 3; ++c) {
    const uint j = c * plane + i;
    precise float v = (pc.flags & F_SPLIT) != 0u ? max(0.0, composite[j] - indirect[j]) + diffuse[j] : composite[j];
    outp[j] = (pc.flags & F_BOOST) != 0u ? v * k : v;
    if ((pc.flags & F_BOOST) != 0u) current[j] *= k;
  }
  for (uint c = 3; c < 6; ++c) outp[c * plane + i] = composite[c * plane + i];
}
