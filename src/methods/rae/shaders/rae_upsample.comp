#version 450
// up2 of the RAE decoder: bilinear x2 with half-pixel centres, every plane (PyTorch's
// interpolate(scale_factor=2, mode="bilinear", align_corners=False), oneDNN's
// resampling_linear): source coordinate (x + 1/2) / 2 - 1/2, clamped at 0, and the next tap
// clamped to the last pixel.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float inp[]; };  // channels planes, width/2 x height/2
layout(std430, binding = 1) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC { uint width, height, channels; } pc;  // the output's size

// The two taps and the weight of the second along one axis of n source pixels.
void taps(uint x, uint n, out uint x0, out uint x1, out float t) {
  const float s = max((float(x) + 0.5) * 0.5 - 0.5, 0.0);
  x0 = min(uint(s), n - 1u);
  x1 = min(x0 + 1u, n - 1u);
  t = s - float(x0);
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint w = pc.width / 2u, h = pc.height / 2u;
  uint x0, x1, y0, y1;
  float tx, ty;
  taps(p.x, w, x0, x1, tx);
  taps(p.y, h, y0, y1, ty);
  for (uint c = 0u; c < pc.channels; ++c) {
    const uint base = c * w * h;
    const float top = mix(inp[base + y0 * w + x0], inp[base + y0 * w + x1], tx);
    const float bottom = mix(inp[base + y1 * w + x0], inp[base + y1 * w + x1], tx);
    outp[c * pc.width * pc.height + p.y * pc.width + p.x] = mix(top, bottom, ty);
  }
}
