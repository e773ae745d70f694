#version 450
// Pass "taa" (motion): TAA follows the specular reprojection on mirror pixels (mode 0), also on
// GlossyReflection ones (mode 1), or on every specular pixel (mode 2: NoSpecReproj, no history
// there), in a lobe split only where metallic (metalness >= 0.5, or no metalness buffer), the
// primary one elsewhere (svgf::Reflections::taaMotion). The whole record (reprojection.glsl's
// eight planes) is copied: TAA reads the previous position (planes 6 and 7) and, for its
// Catmull-Rom fetch, which taps the reprojection accepted (kind, base, weights). `mirrors`
// (SvgfTaaMirrorHistory, modes 0 and 1): 0 mirror pixels follow the specular record, 1 the
// primary one, 2 none (kind 0, position Reprojection::kOffFrame: TAA keeps the current colour).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Cls { float cls[]; };
layout(std430, binding = 1) readonly buffer Metal { float metal[]; };
layout(std430, binding = 2) readonly buffer Primary { uint primary[]; };
layout(std430, binding = 3) readonly buffer Specular { uint specular[]; };
layout(std430, binding = 4) writeonly buffer Out { uint outp[]; };

layout(push_constant) uniform PC { uint width, height, hasMetal, mode, mirrors; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  // Classes: 3 Mirror, 2 GlossyReflection, 0 Diffuse.
  const bool mirror = cls[i] == 3.0, metallic = pc.hasMetal == 0u || metal[i] >= 0.5;
  const bool takes = pc.mode == 2u ? cls[i] != 0.0 : (mirror && pc.mirrors == 0u) || (pc.mode == 1u && cls[i] == 2.0);
  const bool follow = takes && metallic;
  for (uint k = 0u; k < 8u; ++k) outp[k * n + i] = follow ? specular[k * n + i] : primary[k * n + i];
  if (pc.mode != 2u && mirror && metallic && pc.mirrors == 2u) {
    outp[i] = 0u;  // kind None (reprojection.glsl: plane 0's low bits)
    outp[6u * n + i] = floatBitsToUint(-1e6);
    outp[7u * n + i] = floatBitsToUint(-1e6);
  }
}
