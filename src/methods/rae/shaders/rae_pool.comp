#version 450
// 2x2 pooling with stride 2 of every plane: the RAE encoder's max-pooling u_l = maxpool2(h_(l-1))
// (rae_pool), and with RTD_RAE_AVERAGE the average of the albedo/normal features f_l
// (rae_pool_average). The level sizes are even (frames are padded to 2^(L-1)), so no window
// leaves the input. The twin of oneDNN's pooling_max / pooling_avg in rae_model.cpp.
// variant: rae_pool_average RTD_RAE_AVERAGE
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float inp[]; };  // channels planes, 2 width x 2 height
layout(std430, binding = 1) writeonly buffer Out { float outp[]; };

// The output's size; the planes first .. first + channels - 1 of the input are pooled.
layout(push_constant) uniform PC { uint width, height, channels, first; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint inWidth = 2u * pc.width, inPlane = 4u * pc.width * pc.height;
  const uint i = 2u * p.y * inWidth + 2u * p.x;
  for (uint c = 0u; c < pc.channels; ++c) {
    const uint j = (pc.first + c) * inPlane + i;
    const float a = inp[j], b = inp[j + 1u], d = inp[j + inWidth], e = inp[j + inWidth + 1u];
#ifdef RTD_RAE_AVERAGE
    const float v = ((a + b) + (d + e)) * 0.25;
#else
    const float v = max(max(a, b), max(d, e));
#endif
    outp[c * pc.width * pc.height + p.y * pc.width + p.x] = v;
  }
}
