#version 450
// Pass "reflections" (stream albedo): the colour a stream of SVGF's Voorhuis mode is
// demodulated by (svgf::Reflections::stream): its own colour pass (binding 1) when given, else
// for a specular lobe the tint of metals mix(1, albedo, metalness) (flag), else 1; at mirror
// pixels (class 3) times the reflected albedo (Sec. 4.1), each factor floored as
// demodulationFactor (channels <= 1e-3 count as 1).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Cls { float cls[]; };
layout(std430, binding = 1) readonly buffer Base { float base[]; };
layout(std430, binding = 2) readonly buffer Albedo { float albedo[]; };
layout(std430, binding = 3) readonly buffer Metal { float metal[]; };
layout(std430, binding = 4) readonly buffer ReflAlbedo { float reflAlbedo[]; };
layout(std430, binding = 5) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC { uint width, height, hasBase, tint; } pc;

float factor(float a) { return a > 1e-3 ? a : 1.0; }

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  const bool mirror = cls[i] == 3.0;
  for (uint c = 0; c < 3u; ++c) {
    float a = 1.0;
    if (pc.hasBase != 0u) {
      a = base[c * n + i];
    } else if (pc.tint != 0u) {
      const float m = clamp(metal[i], 0.0, 1.0);
      precise float t = 1.0 + m * (albedo[c * n + i] - 1.0);
      a = t;
    }
    if (mirror) a = factor(a) * factor(reflAlbedo[c * n + i]);
    outp[c * n + i] = a;
  }
}
