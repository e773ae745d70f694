#version 450
// Pass "synthesize" of BMFR (Koskela et al. 2019 Eq. 6): every pixel takes its block's weights
// with the noise-free features, normalized as in the fit, y = sum_k alpha_k f'_k, clamped >= 0.
// With excludeEmitters, emitter pixels keep their phase I value (issue 12). Port of
// BmfrCpu::synthesizeRow (src/methods/bmfr/bmfr_simd.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Fits { float fits[]; };
layout(std430, binding = 1) readonly buffer Normals { float normals[]; };
layout(std430, binding = 2) readonly buffer Positions { float positions[]; };
layout(std430, binding = 3) readonly buffer MaterialIds { float materialIds[]; };
layout(std430, binding = 4) readonly buffer Roughness { float roughnessPlane[]; };
layout(std430, binding = 5) writeonly buffer Out { float outp[]; };
layout(std430, binding = 6) readonly buffer Emission { float emission[]; };
layout(std430, binding = 7) readonly buffer Noisy { float noisy[]; };  // phase I colour: planes 0-2

#include "bmfr.glsl"

layout(push_constant) uniform PC {
  uint width, height;
  int originX, originY;
  uint blocksX, size;
  uint features;
  uint pad;
  uvec4 codes;
  float emitterThreshold;
  uint excludeEmitters;  // 1: emitter pixels keep their phase I value (the frame has Buffer::Emission)
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  const uint bx = uint(int(p.x) - pc.originX) / pc.size, by = uint(int(p.y) - pc.originY) / pc.size;
  if (pc.excludeEmitters != 0u && emitterAt(i, plane, pc.emitterThreshold)) {
    for (uint c = 0; c < 3u; ++c) outp[c * plane + i] = noisy[c * plane + i];
    return;
  }
  const uint fit = (by * pc.blocksX + bx) * BMFR_FIT_STRIDE;
  precise vec3 y = vec3(fits[fit], fits[fit + BMFR_MAX_FEATURES], fits[fit + 2u * BMFR_MAX_FEATURES]);
  for (uint k = 1; k < pc.features; ++k) {
    const uint code = featureCode(pc.codes, k);
    const float f = rawFeature(code, i, plane);
    const float centre = fits[fit + BMFR_FIT_CENTRE + k], scale = fits[fit + BMFR_FIT_SCALE + k];
    precise float g;
    if (featureKind(code) == BMFR_POSITION_SQUARED) {
      precise float d = f - fits[fit + BMFR_FIT_POSITION_CENTRE + featureChannel(code)];
      g = (d * d - centre) * scale;
    } else {
      g = (f - centre) * scale;
    }
    // Clamped to the fitted range [-1, 1]: a no-op up to rounding with every pixel as a row.
    g = clamp(g, -1.0, 1.0);
    for (uint c = 0; c < 3u; ++c) y[c] += fits[fit + c * BMFR_MAX_FEATURES + k] * g;
  }
  for (uint c = 0; c < 3u; ++c) outp[c * plane + i] = max(y[c], 0.0);
}
