#version 450
// Import step "hidden area": where Buffer::HiddenArea is set (the pixels an HMD's lens hides,
// Gersthofer Sec. 3.1) a radiance buffer or the normal becomes 0, so the pixel is background to
// every method. Port of applyHiddenArea (src/core/frame_data.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) buffer Planes { float planes[]; };
layout(std430, binding = 1) readonly buffer Hidden { float hidden[]; };

layout(push_constant) uniform PC { uint width, height, channels; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  if (!(hidden[i] > 0.5)) return;
  for (uint c = 0; c < pc.channels; ++c) planes[c * plane + i] = 0.0;
}
