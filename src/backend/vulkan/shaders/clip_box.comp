#version 450
// Pass "clip": the neighbourhood-clipping box of Voorhuis 2018 Sec. 4.2.3, in four dispatches
// (`mode`): 0 and 1 the separable Gaussian of the current frame along rows, then columns;
// 2 and 3 the min / max over the window along rows, then columns, where mode 3 also opens the
// box to (-inf, inf) on pixels of class 0 (diffuse: not clipped). Images are RGB (modes 0, 1,
// and the input of 2) or low RGB + high RGB (the output of 2, both sides of 3). Borders clamp
// to the edge. Port of clipBox (src/passes/neighbourhood_clipping.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float inp[]; };
layout(std430, binding = 1) writeonly buffer Out { float outp[]; };
layout(std430, binding = 2) readonly buffer Cls { float cls[]; };

layout(push_constant) uniform PC {
  uint width, height, mode;
  int radius;        // Gaussian radius (modes 0, 1); window radius (modes 2, 3)
  uint masked;       // mode 3: classes at binding 2
  float weights[7];  // normalized Gaussian weights (clipGaussianWeights), radius <= 3
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const int W = int(pc.width), H = int(pc.height), x = int(p.x), y = int(p.y), R = pc.radius;
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  const bool rows = pc.mode == 0u || pc.mode == 2u;
  if (pc.mode <= 1u) {
    for (uint c = 0; c < 3u; ++c) {
      precise float v = 0.0;
      for (int k = -R; k <= R; ++k) {
        const int qx = rows ? clamp(x + k, 0, W - 1) : x, qy = rows ? y : clamp(y + k, 0, H - 1);
        v += pc.weights[k + R] * inp[c * n + uint(qy * W + qx)];
      }
      outp[c * n + i] = v;
    }
    return;
  }
  const float inf = uintBitsToFloat(0x7f800000u);
  if (pc.mode == 3u && pc.masked != 0u && cls[i] == 0.0) {
    for (uint c = 0; c < 3u; ++c) {
      outp[c * n + i] = -inf;
      outp[(3u + c) * n + i] = inf;
    }
    return;
  }
  for (uint c = 0; c < 3u; ++c) {
    float lo = inf, hi = -inf;
    const int a = rows ? max(0, x - R) : max(0, y - R), b = rows ? min(W - 1, x + R) : min(H - 1, y + R);
    for (int k = a; k <= b; ++k) {
      const uint j = rows ? uint(y * W + k) : uint(k * W + x);
      // Mode 2 reads the blurred RGB for both sides; mode 3 the row minima and maxima.
      lo = min(lo, inp[c * n + j]);
      hi = max(hi, inp[(pc.mode == 2u ? c : 3u + c) * n + j]);
    }
    outp[c * n + i] = lo;
    outp[(3u + c) * n + i] = hi;
  }
}
