#version 450
// Pass "taa": the surface keys of TAA's own-surface clamp box (TaaSettings::taaOwnSurface):
// (object id * 4 + class) in bits 0-30, bit 31 at the emitters the filter leaves out (the
// emitter test of emitter_guide.comp). Port of taaSurfaceKeys (src/passes/taa_keys.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Cls { float cls[]; };
layout(std430, binding = 1) readonly buffer Obj { float objectId[]; };
layout(std430, binding = 2) readonly buffer Emission { float emission[]; };
layout(std430, binding = 3) readonly buffer Albedo { float albedo[]; };
layout(std430, binding = 4) writeonly buffer Out { uint keys[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint hasCls, hasObject;
  uint emitters;  // 0: none; 1: every emitter; 2: those with an albedo above 1 (reflectanceless)
  float threshold;
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  const uint object = pc.hasObject != 0u ? uint(int(objectId[i])) : 0u;
  uint key = (object * 4u + (pc.hasCls != 0u ? uint(cls[i]) : 0u)) & 0x7fffffffu;
  if (pc.emitters != 0u) {
    bool emitter = max(emission[i], max(emission[plane + i], emission[2u * plane + i])) > pc.threshold;
    if (emitter && pc.emitters == 2u) emitter = max(albedo[i], max(albedo[plane + i], albedo[2u * plane + i])) > 1.0;
    if (emitter) key |= 0x80000000u;
  }
  keys[i] = key;
}
