#version 450
// One 3x3 "same" convolution of the RAE (zero padding 1) over the concatenation of up to three
// inputs cat(in0, in1, in2) -- the recurrent block's cat(a_l, h_l^(t-1)), the decoder's
// cat(up2(d_(l+1)), h_l, f_l) -- read in place, so no concatenated tensor is built; then bias
// and, when `activation` is set, the leaky ReLU. The twin of the oneDNN convolutions of
// src/methods/rae/rae_model.cpp.
//
// A 16x16 workgroup computes kOutGroup output channels (16; 4 in the variant rae_conv_narrow,
// for the 3-channel last layer) of a 16x16 tile: the input channels are walked kChunk at a
// time through an 18x18 shared-memory tile (the tile and its 1-pixel apron, zeros outside the
// level), so each input value is read from memory ~1.27 times per output group instead of 9.
// Workgroup row gl_WorkGroupID.y = output group * tilesY + tile row.
// variant: rae_conv_narrow RTD_RAE_NARROW
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer In0 { float in0[]; };
layout(std430, binding = 1) readonly buffer In1 { float in1[]; };
layout(std430, binding = 2) readonly buffer In2 { float in2[]; };
// Every convolution's weight [out][in][3][3] (PyTorch's layout) and bias [out], at offsets.
layout(std430, binding = 3) readonly buffer Weights { float weights[]; };
layout(std430, binding = 4) writeonly buffer Out { float outp[]; };

layout(push_constant) uniform PC {
  uint width, height, tilesY;            // the level's size; tile rows per output group
  uint channels0, channels1, channels2;  // input channels of each part (0: absent)
  uint first0, first1, first2;           // the part's first plane in its buffer
  uint outChannels, weightOffset, biasOffset;
  uint activation;
  float slope;
} pc;

#ifdef RTD_RAE_NARROW
const uint kOutGroup = 4u;
#else
const uint kOutGroup = 16u;
#endif
const uint kTile = 18u, kChunk = 8u;
shared float tile[kChunk * kTile * kTile];

// Input channel ci of the concatenation at pixel index i of its plane.
float load(uint ci, uint i) {
  const uint plane = pc.width * pc.height;
  if (ci < pc.channels0) return in0[(pc.first0 + ci) * plane + i];
  ci -= pc.channels0;
  if (ci < pc.channels1) return in1[(pc.first1 + ci) * plane + i];
  ci -= pc.channels1;
  return in2[(pc.first2 + ci) * plane + i];
}

void main() {
  const uint group = gl_WorkGroupID.y / pc.tilesY;
  const uvec2 origin = uvec2(gl_WorkGroupID.x, gl_WorkGroupID.y % pc.tilesY) * 16u;
  const uvec2 p = origin + gl_LocalInvocationID.xy;
  const uint local = gl_LocalInvocationIndex;
  const uint inChannels = pc.channels0 + pc.channels1 + pc.channels2;
  const uint o0 = group * kOutGroup;
  float acc[kOutGroup];
  for (uint o = 0u; o < kOutGroup; ++o) acc[o] = 0.0;

  for (uint c0 = 0u; c0 < inChannels; c0 += kChunk) {
    const uint chunk = min(kChunk, inChannels - c0);
    // Every invocation helps to load (those outside the level too: no early return before a barrier).
    for (uint k = local; k < chunk * kTile * kTile; k += 256u) {
      const uint c = k / (kTile * kTile), t = k % (kTile * kTile);
      const ivec2 q = ivec2(origin) + ivec2(t % kTile, t / kTile) - 1;
      const bool inside = q.x >= 0 && q.y >= 0 && q.x < int(pc.width) && q.y < int(pc.height);
      tile[k] = inside ? load(c0 + c, uint(q.y) * pc.width + uint(q.x)) : 0.0;
    }
    barrier();
    for (uint c = 0u; c < chunk; ++c) {
      float v[9];
      for (uint dy = 0u; dy < 3u; ++dy)
        for (uint dx = 0u; dx < 3u; ++dx)
          v[dy * 3u + dx] = tile[c * kTile * kTile + (gl_LocalInvocationID.y + dy) * kTile + gl_LocalInvocationID.x + dx];
      for (uint o = 0u; o < kOutGroup; ++o) {
        // Rows past the last output channel repeat it (the weights are read in bounds; not stored).
        const uint w = pc.weightOffset + (min(o0 + o, pc.outChannels - 1u) * inChannels + c0 + c) * 9u;
        float s = acc[o];
        for (uint k = 0u; k < 9u; ++k) s += v[k] * weights[w + k];
        acc[o] = s;
      }
    }
    barrier();
  }

  if (outside(p, pc.width, pc.height)) return;
  const uint plane = pc.width * pc.height, i = p.y * pc.width + p.x;
  for (uint o = 0u; o < kOutGroup && o0 + o < pc.outChannels; ++o) {
    const float y = acc[o] + weights[pc.biasOffset + o0 + o];
    outp[(o0 + o) * plane + i] = pc.activation != 0u && y < 0.0 ? pc.slope * y : y;
  }
}
