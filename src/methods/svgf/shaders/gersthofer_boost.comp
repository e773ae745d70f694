#version 450
// Gersthofer Eq. 3.1: the factor 1/c of a sampled pixel whose reprojection failed (no valid
// tap, or taps holding no data: the gathered previous history length rounds to 0), 1 elsewhere
// (one plane; the composite pass applies it to this frame's filter input). c is pc.coverage,
// or sampled / visible from gersthofer_coverage where pc.coverage is 0. Port of
// svgf::boostDisoccluded.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Rp { uint rp[]; };
layout(std430, binding = 1) readonly buffer Hist { float hist[]; };  // previous accumulator: length is plane 5
layout(std430, binding = 2) readonly buffer Mask { float sampleMask[]; };
layout(std430, binding = 3) readonly buffer Counter { uint counter[]; };
layout(std430, binding = 4) writeonly buffer Factor { float factor[]; };

float histAt(uint j) { return hist[j]; }
#define RP_GATHER
#include "reprojection.glsl"

layout(push_constant) uniform PC { uint width, height; float coverage; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint w = pc.width, plane = w * pc.height, i = p.y * w + p.x;
  const float c = pc.coverage > 0.0 ? pc.coverage : (counter[1] > 0u ? float(counter[0]) / float(counter[1]) : 1.0);
  const bool boost = sampleMask[i] != 0.0 && c > 0.0 &&
                     (rpKind(i) == RP_NONE || floor(gatherPlane(i, 5u * plane, w, plane) + 0.5) < 1.0);
  factor[i] = boost ? 1.0 / c : 1.0;
}
