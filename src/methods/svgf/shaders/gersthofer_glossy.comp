#version 450
// Gersthofer's glossy weights, per pixel (Sec. 3.4.3): binding 2 = 1 / w_r with w_r = 0.01 +
// sqrt(roughness) where the BRDF is glossy (metalness >= glossyMetalness, or everywhere
// without metalness), else 1; binding 3 = 1 - roughness, the factor of w_zi (Eq. 3.2).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Rough { float roughness[]; };
layout(std430, binding = 1) readonly buffer Metal { float metalness[]; };
layout(std430, binding = 2) writeonly buffer Centre { float centreScale[]; };
layout(std430, binding = 3) writeonly buffer ZiScale { float ziScale[]; };

layout(push_constant) uniform PC { uint width, height, hasMetalness; float glossyMetalness; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x;
  const float r = roughness[i];
  const bool glossy = pc.hasMetalness == 0u || metalness[i] >= pc.glossyMetalness;
  centreScale[i] = glossy ? 1.0 / (0.01 + sqrt(max(0.0, r))) : 1.0;
  ziScale[i] = 1.0 - clamp(r, 0.0, 1.0);
}
