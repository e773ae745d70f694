#version 450
// Pass "gradient" of A-SVGF (Schied et al. 2018; Higginson Sec. 2.3.1): per 3x3 stratum, the
// temporal gradient G = scale * (|L_cur - L_prev| / max(L_prev, L_cur))^2 (0 where both are 0)
// of the pixel whose gradientSample is set, with its features as the stratum's guide; strata
// without a sample are invalid (their centre pixel's features). One invocation per stratum.
// Port of asvgf::gradientFromSamples.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Sample { float sampleMask[]; };
layout(std430, binding = 1) readonly buffer Prev { float previous[]; };
layout(std430, binding = 2) readonly buffer Cur { float current[]; };
#include "asvgf_stratum.glsl"

layout(push_constant) uniform PC {
  uint width, height;    // pixels
  uint gwidth, gheight;  // strata
  float scale;
} pc;

float temporalGradient(float prev, float cur) {
  const float m = max(prev, cur);
  if (!(m > 0.0)) return 0.0;
  const float r = abs(cur - prev) / m;
  return r * r;
}

void main() {
  const uvec2 s = gl_GlobalInvocationID.xy;
  if (outside(s, pc.gwidth, pc.gheight)) return;
  const uint W = pc.width, H = pc.height;
  int found = -1;
  for (uint y = s.y * STRATUM; y < min(H, (s.y + 1u) * STRATUM) && found < 0; ++y)
    for (uint x = s.x * STRATUM; x < min(W, (s.x + 1u) * STRATUM); ++x)
      if (sampleMask[y * W + x] > 0.5) {
        found = int(y * W + x);
        break;
      }
  const bool isValid = found >= 0;
  const uint j = isValid ? uint(found) : min(H - 1u, s.y * STRATUM + 1u) * W + min(W - 1u, s.x * STRATUM + 1u);
  const float g = isValid ? pc.scale * temporalGradient(previous[j], current[j]) : 0.0;
  writeStratum(s.y * pc.gwidth + s.x, pc.gwidth * pc.gheight, j, W * H, g, isValid);
}
