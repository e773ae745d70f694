#version 450
// Pass "sum": adds one radiance stream's filtered illumination to the sum of streams,
// remodulated by the stream's own demodulation colour (binding 3, when `times`) and divided by
// the albedo (binding 1, when `divide`) so that the shared remodulation by the albedo restores
// it exactly. Port of SvgfCpu::addStream.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float img[]; };  // R, G, B (, lum, var)
layout(std430, binding = 1) readonly buffer Albedo { float albedo[]; };
layout(std430, binding = 2) buffer Sum { float sum[]; };
layout(std430, binding = 3) readonly buffer StreamAlbedo { float streamAlbedo[]; };

layout(push_constant) uniform PC { uint width, height, first, divide, times; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  for (uint c = 0; c < 3; ++c) {
    float v = img[c * plane + i];
    if (pc.times != 0u) {
      const float m = streamAlbedo[c * plane + i];
      v *= m > 1e-3 ? m : 1.0;
    }
    if (pc.divide != 0u) {
      const float a = albedo[c * plane + i];
      v /= a > 1e-3 ? a : 1.0;
    }
    sum[c * plane + i] = pc.first != 0u ? v : sum[c * plane + i] + v;
  }
}
