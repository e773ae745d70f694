#version 450
// Gersthofer's coverage c (Eq. 3.1), measured: counts the sampled (sampleMask != 0) and the
// visible (hiddenArea <= 0.5) pixels into counter[0], counter[1] (zeroed before). One atomic per
// workgroup. Port of svgf::sampleCoverage.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Mask { float sampleMask[]; };
layout(std430, binding = 1) readonly buffer Hidden { float hidden[]; };
layout(std430, binding = 2) buffer Counter { uint counter[]; };

layout(push_constant) uniform PC { uint width, height, hasHidden; } pc;

shared uint sSampled, sVisible;

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    sSampled = 0u;
    sVisible = 0u;
  }
  barrier();
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (!outside(p, pc.width, pc.height)) {
    const uint i = p.y * pc.width + p.x;
    if (pc.hasHidden == 0u || !(hidden[i] > 0.5)) {
      atomicAdd(sVisible, 1u);
      if (sampleMask[i] != 0.0) atomicAdd(sSampled, 1u);
    }
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    atomicAdd(counter[0], sSampled);
    atomicAdd(counter[1], sVisible);
  }
}
