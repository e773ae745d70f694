#version 450
// Pass "antilag" of asvgf with gradientSource = historyAntilag (NOT A-SVGF; for inputs without
// gradient samples): per 3x3 stratum, over its pixels with history, the mean current luminance
// Lc, the mean reprojected history luminance Lh and variance V (last frame's moments);
// d = max(0, |Lc - Lh| - k sqrt(V / n)), G = scale * (d / max(Lc, Lh))^2.
// Port of asvgf::gradientFromHistory.
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
  float scale, noiseSigmas;
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
  float g = 0.0;
  if (n > 0) {
    const float lc = sc / float(n), lh = sh / float(n);
    const float d = max(0.0, abs(lc - lh) - pc.noiseSigmas * sqrt(sv / float(n) / float(n)));
    const float m = max(lc, lh);
    g = m > 0.0 ? pc.scale * (d / m) * (d / m) : 0.0;
  }
  const uint j = min(H - 1u, s.y * STRATUM + 1u) * W + min(W - 1u, s.x * STRATUM + 1u);
  writeStratum(s.y * pc.gwidth + s.x, pc.gwidth * pc.gheight, j, plane, g, n > 0);
}
