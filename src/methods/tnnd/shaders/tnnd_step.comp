#version 450
// Pass "step<k>" of TNND: one automaton iteration (Higginson Eqs. 2.15-2.17). Perception of
// the 3x3 neighbourhood with replicated borders: s (9), Gaussian [1 2 1]x[1 2 1]/16 of RGB (3),
// Laplace = Gaussian - identity (9), Sobel x [-1 0 1]x[1 2 1]/8 (9), Sobel y (9); then
// next = s + sigmoid(p W) + b. Port of tnnd::step (src/methods/tnnd/tnnd_model.cpp).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Weights { float weights[]; };  // W [39][9] row-major, then b [9]
layout(std430, binding = 1) readonly buffer In { float s[]; };             // 9 planes
layout(std430, binding = 2) writeonly buffer Out { float next[]; };

layout(push_constant) uniform PC { uint width, height; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height;
  const uint xs[3] = uint[3](uint(max(int(p.x) - 1, 0)), p.x, min(p.x + 1u, pc.width - 1u));
  const uint ys[3] = uint[3](uint(max(int(p.y) - 1, 0)), p.y, min(p.y + 1u, pc.height - 1u));
  float z[9];
  for (uint j = 0; j < 9u; ++j) z[j] = 0.0;
  for (uint c = 0; c < 9u; ++c) {
    float v[3], d[3];  // per column: [1 2 1] and [-1 0 1] down the column
    for (uint k = 0; k < 3u; ++k) {
      const float a = s[c * plane + ys[0] * pc.width + xs[k]];
      const float b = s[c * plane + ys[1] * pc.width + xs[k]];
      const float e = s[c * plane + ys[2] * pc.width + xs[k]];
      v[k] = a + 2.0 * b + e;
      d[k] = e - a;
    }
    const float centre = s[c * plane + p.y * pc.width + p.x];
    const float g = (v[0] + 2.0 * v[1] + v[2]) * (1.0 / 16.0);
    const float sx = (v[2] - v[0]) * (1.0 / 8.0);
    const float sy = (d[0] + 2.0 * d[1] + d[2]) * (1.0 / 8.0);
    for (uint j = 0; j < 9u; ++j) {
      float acc = z[j] + centre * weights[c * 9u + j];                      // s
      if (c < 3u) acc += g * weights[(9u + c) * 9u + j];                    // gauss(rgb)
      acc += (g - centre) * weights[(12u + c) * 9u + j];                    // laplace
      acc += sx * weights[(21u + c) * 9u + j];                              // sobel x
      acc += sy * weights[(30u + c) * 9u + j];                              // sobel y
      z[j] = acc;
    }
  }
  const uint i = p.y * pc.width + p.x;
  for (uint j = 0; j < 9u; ++j)
    next[j * plane + i] = s[j * plane + i] + 1.0 / (1.0 + exp(-z[j])) + weights[351u + j];
}
