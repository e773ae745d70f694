#version 450
// Pass "taa" (motion): TAA follows the specular reprojection on mirror pixels (mode 0), also on
// GlossyReflection ones (mode 1), or on every specular pixel (mode 2: NoSpecReproj, no history
// there), in a lobe split only where metallic (metalness >= 0.5, or no metalness buffer), the
// primary one elsewhere (svgf::Reflections::taaMotion). The whole record (reprojection.glsl's
// eight planes) is copied: TAA reads the previous position (planes 6 and 7) and, for its
// Catmull-Rom fetch, which taps the reprojection accepted (kind, base, weights).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Cls { float cls[]; };
layout(std430, binding = 1) readonly buffer Metal { float metal[]; };
layout(std430, binding = 2) readonly buffer Primary { uint primary[]; };
layout(std430, binding = 3) readonly buffer Specular { uint specular[]; };
layout(std430, binding = 4) writeonly buffer Out { uint outp[]; };

layout(push_constant) uniform PC { uint width, height, hasMetal, mode; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  // Classes: 3 Mirror, 2 GlossyReflection, 0 Diffuse.
  const bool takes = pc.mode == 2u ? cls[i] != 0.0 : cls[i] == 3.0 || (pc.mode == 1u && cls[i] == 2.0);
  const bool follow = takes && (pc.hasMetal == 0u || metal[i] >= 0.5);
  for (uint k = 0u; k < 8u; ++k) outp[k * n + i] = follow ? specular[k * n + i] : primary[k * n + i];
}
