#version 450
// Pass "antilag" of asvgf with gradientSource = historyAntilag (NOT A-SVGF; for inputs without
// gradient samples): per 3x3 stratum, over its pixels with history, the mean current luminance
// Lc (plane 0), the mean reprojected history luminance Lh (plane 1) and the variance of Lc's
// mean V / n (plane 4), V from last frame's moments; asvgf_antilag_gradient.comp turns them
// into G after the gradient's a-trous levels. Port of asvgf::historyLuminances.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Rp { uint rp[]; };
layout(std430, binding = 1) readonly buffer Cur { float cur[]; };    // this frame, demodulated
layout(std430, binding = 2) readonly buffer Hist { float hist[]; };  // last frame: R, G, B, m1, m2, length
#include "asvgf_stratum.glsl"

float histAt(uint j) { return hist[j]; }
#define RP_GATHER
#include "reprojection.glsl"

layout(push_constant) uniform PC {
  uint width, height;
  uint gwidth, gheight;
  uint luminanceMode;
} pc;

void main() {
  const uvec2 s = gl_GlobalInvocationID.xy;
  if (outside(s, pc.gwidth, pc.gheight)) return;
  const uint W = pc.width, H = pc.height, plane = W * H;
  float sc = 0.0, sh = 0.0, sv = 0.0;
  int n = 0;
  for (uint y = s.y * STRATUM; y < min(H, (s.y + 1u) * STRATUM); ++y)
    for (uint x = s.x * STRATUM; x < min(W, (s.x + 1u) * STRATUM); ++x) {
      const uint i = y * W + x;
      if (rpKind(i) == RP_NONE) continue;
      const float lh = gatherPlane(i, 3u * plane, W, plane);
      sc += momentLuminance(pc.luminanceMode, vec3(cur[i], cur[plane + i], cur[2u * plane + i]));
      sh += lh;
      sv += max(0.0, gatherPlane(i, 4u * plane, W, plane) - lh * lh);
      ++n;
    }
  const uint j = min(H - 1u, s.y * STRATUM + 1u) * W + min(W - 1u, s.x * STRATUM + 1u);
  const uint st = s.y * pc.gwidth + s.x, gplane = pc.gwidth * pc.gheight;
  writeStratum(st, gplane, j, plane, n > 0 ? sc / float(n) : 0.0, n > 0);
  if (n > 0) {
    level[gplane + st] = sh / float(n);
    level[4u * gplane + st] = sv / float(n) / float(n);
  }
}
