#version 450
// The last step of Gersthofer's output (Sec. 3.5), in place: the ACES tone map (Narkowicz fit,
// src/passes/tonemap.h) if asked, and 0 in the hidden area.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) buffer Img { float img[]; };
layout(std430, binding = 1) readonly buffer Hidden { float hidden[]; };

layout(push_constant) uniform PC { uint width, height, aces, hasHidden; } pc;

float acesNarkowicz(float x) {
  x = max(x, 0.0);
  precise float num = x * (2.51 * x + 0.03);
  precise float den = x * (2.43 * x + 0.59) + 0.14;
  return clamp(num / den, 0.0, 1.0);
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  const bool zero = pc.hasHidden != 0u && hidden[i] > 0.5;
  for (uint k = 0; k < 3; ++k) {
    const uint j = k * plane + i;
    img[j] = zero ? 0.0 : (pc.aces != 0u ? acesNarkowicz(img[j]) : img[j]);
  }
}
