#version 450
// Pass "reflections" (classes): the surface class of each pixel (Voorhuis 2018; SurfaceClass in
// src/passes/reflection_reprojection.h) by the primary hit's roughness: 0 diffuse, 1 glossy
// (primary motion), 2 glossy with reflection motion, 3 mirror. Port of classifySurfaces.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Normal { float normal[]; };
layout(std430, binding = 1) readonly buffer Rough { float roughness[]; };
layout(std430, binding = 2) readonly buffer Metal { float metalness[]; };
layout(std430, binding = 3) writeonly buffer Out { float cls[]; };

layout(push_constant) uniform PC {
  uint width, height;
  float pureSpecular, reflection, diffuse;
  uint specularLobe, hasRoughness, hasMetalness;  // hasMetalness is ignored for a specular lobe
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  precise float len2 = normal[i] * normal[i] + normal[n + i] * normal[n + i] + normal[2u * n + i] * normal[2u * n + i];
  float c = 0.0;
  if (!(len2 < 0.25)) {
    if (pc.hasRoughness == 0u) {
      c = pc.specularLobe != 0u ? 1.0 : 0.0;
    } else {
      const float r = roughness[i];
      const bool metalRule = pc.specularLobe == 0u && pc.hasMetalness != 0u;
      if (r >= pc.diffuse) c = 0.0;
      else if (r >= pc.reflection) c = 1.0;
      else if (r < pc.pureSpecular && (!metalRule || metalness[i] >= 0.5)) c = 3.0;
      else c = 2.0;
    }
  }
  cls[i] = c;
}
