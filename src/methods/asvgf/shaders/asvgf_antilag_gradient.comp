#version 450
// The end of pass "gradientAtrous" with gradientSource = historyAntilag (NOT A-SVGF): per
// stratum of the filtered level, G = scale * (max(0, |Lc - Lh| - k sqrt(V)) / max(Lc, Lh))^2
// (0 where both are 0), written over plane 0 (Lc), where the accumulation reads G.
// Port of asvgf::historyAntilagGradient.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) buffer Level { float level[]; };  // Lc, Lh, -, -, V

layout(push_constant) uniform PC {
  uint gwidth, gheight;
  float noiseSigmas, scale;
} pc;

void main() {
  const uvec2 s = gl_GlobalInvocationID.xy;
  if (outside(s, pc.gwidth, pc.gheight)) return;
  const uint gplane = pc.gwidth * pc.gheight, i = s.y * pc.gwidth + s.x;
  const float lc = level[i], lh = level[gplane + i], v = level[4u * gplane + i];
  const float m = max(lc, lh);
  float g = 0.0;
  if (m > 0.0) {
    const float d = max(0.0, abs(lc - lh) - pc.noiseSigmas * sqrt(max(0.0, v)));
    g = pc.scale * (d / m) * (d / m);
  }
  level[i] = g;
}
