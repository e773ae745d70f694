#version 450
// Pass "taa" (motion): with the colour split into lobes, TAA follows the specular
// reprojection on specular pixels that are metallic (metalness >= 0.5, or no metalness
// buffer), the primary one elsewhere (svgf::Reflections::taaMotion). TAA reads only the
// previous positions (record planes 6 and 7), so only those are written.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Cls { float cls[]; };
layout(std430, binding = 1) readonly buffer Metal { float metal[]; };
layout(std430, binding = 2) readonly buffer Primary { uint primary[]; };
layout(std430, binding = 3) readonly buffer Specular { uint specular[]; };
layout(std430, binding = 4) writeonly buffer Out { uint outp[]; };

layout(push_constant) uniform PC { uint width, height, hasMetal; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  const bool follow = cls[i] != 0.0 && (pc.hasMetal == 0u || metal[i] >= 0.5);
  for (uint k = 6u; k < 8u; ++k) outp[k * n + i] = follow ? specular[k * n + i] : primary[k * n + i];
}
