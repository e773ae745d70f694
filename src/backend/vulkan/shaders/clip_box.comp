#version 450
// Pass "clip": the neighbourhood-clipping box of Voorhuis 2018 Sec. 4.2.3, in four dispatches
// (`mode`): 0 and 1 the separable Gaussian of the current frame along rows, then columns;
// 2 and 3 the min / max over the window along rows, then columns, where mode 3 also opens the
// box to (-inf, inf) on pixels of class 0 (diffuse: not clipped). Images are RGB (modes 0, 1,
// and the input of 2) or low RGB + high RGB (the output of 2, both sides of 3). Borders clamp
// to the edge. Port of clipBox (src/passes/neighbourhood_clipping.cpp).
// With the pixel's own surface (clipBox's `surface`, SvgfSettings::clipOwnSurface) two
// dispatches instead: mode 4 the 7x7 Gaussian at clipped pixels (class != 0) over the taps of
// the same class and object id (binding 3, when `hasObject`), renormalized; mode 5 the min /
// max over the window of those of the pixel's class and object id, (-inf, inf) on class 0.
// Non-separable, as clipBoxOnSurfaces, in the same order.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In { float inp[]; };
layout(std430, binding = 1) writeonly buffer Out { float outp[]; };
layout(std430, binding = 2) readonly buffer Cls { float cls[]; };
layout(std430, binding = 3) readonly buffer Obj { float objectId[]; };

layout(push_constant) uniform PC {
  uint width, height, mode;
  int radius;        // Gaussian radius (modes 0, 1); window radius (modes 2, 3)
  uint masked;       // mode 3: classes at binding 2
  float weights[7];  // normalized Gaussian weights (clipGaussianWeights), radius <= 3
  uint hasObject;    // modes 4, 5: object ids at binding 3
} pc;

bool sameSurface(uint i, uint j) {
  return cls[j] == cls[i] && (pc.hasObject == 0u || objectId[j] == objectId[i]);
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const int W = int(pc.width), H = int(pc.height), x = int(p.x), y = int(p.y), R = pc.radius;
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  if (pc.mode == 4u) {
    if (cls[i] == 0.0) return;
    precise vec3 v = vec3(0.0);
    precise float sum = 0.0;
    for (int l = -R; l <= R; ++l) {
      const int qy = clamp(y + l, 0, H - 1);
      for (int k = -R; k <= R; ++k) {
        const uint j = uint(qy * W + clamp(x + k, 0, W - 1));
        if (!sameSurface(i, j)) continue;
        precise float g = pc.weights[l + R] * pc.weights[k + R];
        sum += g;
        for (uint c = 0; c < 3u; ++c) v[c] += g * inp[c * n + j];
      }
    }
    for (uint c = 0; c < 3u; ++c) outp[c * n + i] = v[c] / sum;
    return;
  }
  if (pc.mode == 5u) {
    const float inf5 = uintBitsToFloat(0x7f800000u);
    vec3 lo = vec3(inf5), hi = vec3(-inf5);
    if (cls[i] == 0.0) {
      lo = vec3(-inf5);
      hi = vec3(inf5);
    } else {
      for (int qy = max(0, y - R); qy <= min(H - 1, y + R); ++qy)
        for (int qx = max(0, x - R); qx <= min(W - 1, x + R); ++qx) {
          const uint j = uint(qy * W + qx);
          if (!sameSurface(i, j)) continue;
          for (uint c = 0; c < 3u; ++c) {
            lo[c] = min(lo[c], inp[c * n + j]);
            hi[c] = max(hi[c], inp[c * n + j]);
          }
        }
    }
    for (uint c = 0; c < 3u; ++c) {
      outp[c * n + i] = lo[c];
      outp[(3u + c) * n + i] = hi[c];
    }
    return;
  }
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
