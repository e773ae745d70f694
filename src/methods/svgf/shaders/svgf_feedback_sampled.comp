#version 450
// Feedback of the a-trous level into the colour history in the progressive mode (Dundr Sec. 5):
// only pixels sampled this frame take the filtered value; feeding it back everywhere would blur
// the untouched history again every frame. Port of SvgfCpu::feedbackSampled.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Level { float level[]; };  // R, G, B (, lum, var)
layout(std430, binding = 1) readonly buffer Mask { float sampleMask[]; };
layout(std430, binding = 2) buffer History { float history[]; };       // R, G, B (, moments, length)

layout(push_constant) uniform PC { uint width, height; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  if (sampleMask[i] == 0.0) return;
  for (uint c = 0; c < 3; ++c) history[c * plane + i] = level[c * plane + i];
}
