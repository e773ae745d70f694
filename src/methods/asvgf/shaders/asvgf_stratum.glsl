// Shared by A-SVGF's gradient passes (asvgf_gradient.comp, asvgf_antilag.comp): the outputs of
// one stratum, the level-0 image of the gradient's a-trous levels and its guide (the twin of
// takeFeatures / setStratum in src/methods/asvgf/asvgf_passes.cpp).
#define STRATUM 3u

layout(std430, binding = 3) readonly buffer Depth { float depth[]; };
layout(std430, binding = 4) readonly buffer Normal { float normal[]; };
layout(std430, binding = 5) readonly buffer Grad { float grad[]; };
layout(std430, binding = 6) writeonly buffer Level { float level[]; };  // G, 0, 0, lum 0, var 0
layout(std430, binding = 7) writeonly buffer Valid { float valid[]; };
layout(std430, binding = 8) writeonly buffer GDepth { float gdepth[]; };
layout(std430, binding = 9) writeonly buffer GNormal { float gnormal[]; };
layout(std430, binding = 10) writeonly buffer GGrad { float ggrad[]; };

// Stratum s (of gw * gh) takes the features of pixel j (of a w * h frame); its depth gradient
// is per pixel there and per stratum (3 pixels) here.
void writeStratum(uint s, uint gplane, uint j, uint plane, float g, bool isValid) {
  gdepth[s] = depth[j];
  for (uint c = 0u; c < 3u; ++c) gnormal[c * gplane + s] = normal[c * plane + j];
  ggrad[s] = float(STRATUM) * grad[j];
  ggrad[gplane + s] = float(STRATUM) * grad[plane + j];
  level[s] = isValid ? g : 0.0;
  for (uint c = 1u; c < 5u; ++c) level[c * gplane + s] = 0.0;
  valid[s] = isValid ? 1.0 : 0.0;
}
