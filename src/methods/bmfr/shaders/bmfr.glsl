// Shared by BMFR's shaders (fit, synthesize): feature codes, the block grid's mirroring and the
// integer hash of the regularization noise and the sub-sampled rows. GLSL twins of blocks.h and
// bmfr_common.h, bit-identical to them (integer arithmetic wraps modulo 2^32 in both).
//
// The including shader declares the feature planes as `normals`, `positions`, `materialIds`
// and `roughnessPlane`, and Buffer::Emission as `emission` (float[]; a dummy binding where the
// frame lacks the buffer).

// A feature column: kind (bmfr::FeatureKind) in bits 4-7, channel in bits 0-3; four codes per
// uint of the push constants.
#define BMFR_CONSTANT 0u
#define BMFR_NORMAL 1u
#define BMFR_POSITION 2u
#define BMFR_POSITION_SQUARED 3u
#define BMFR_MATERIAL_ID 4u
#define BMFR_ROUGHNESS 5u
#define BMFR_MAX_FEATURES 12
// bmfr::kConstantFeature: a feature whose half range is at most this fraction of its magnitude
// is constant on the block.
#define BMFR_CONSTANT_FEATURE 1e-6
#define BMFR_MAX_COLUMNS 15
// Floats per block in the fit buffer: alpha[3][12], centre[12], scale[12], positionCentre[3].
#define BMFR_FIT_STRIDE 64u
#define BMFR_FIT_CENTRE 36u
#define BMFR_FIT_SCALE 48u
#define BMFR_FIT_POSITION_CENTRE 60u

uint featureCode(uvec4 codes, uint k) { return (codes[k >> 2] >> ((k & 3u) * 8u)) & 0xffu; }
uint featureKind(uint code) { return code >> 4; }
uint featureChannel(uint code) { return code & 15u; }

// Raw (un-normalized) value of feature `code` at pixel i of planes of `plane` elements.
float rawFeature(uint code, uint i, uint plane) {
  const uint kind = featureKind(code), c = featureChannel(code);
  if (kind == BMFR_NORMAL) return normals[c * plane + i];
  if (kind == BMFR_POSITION || kind == BMFR_POSITION_SQUARED) return positions[c * plane + i];
  if (kind == BMFR_MATERIAL_ID) return materialIds[i];
  if (kind == BMFR_ROUGHNESS) return roughnessPlane[i];
  return 1.0;
}

// Issue 12: pixel i is an emitter (emitterPixel, src/passes/emitters.h): the largest channel of
// its emission above `threshold`.
bool emitterAt(uint i, uint plane, float threshold) {
  return max(emission[i], max(emission[plane + i], emission[2u * plane + i])) > threshold;
}

// bmfr::mirror: -1 -> 0, n -> n - 1, clamped for blocks wider than the image.
int mirrorIndex(int i, int n) {
  if (i < 0) i = -i - 1;
  else if (i >= n) i = 2 * n - i - 1;
  return clamp(i, 0, n - 1);
}

// bmfr::hashUniform: a PCG output permutation to a uniform float in [0, 1) (exact: 24 bits).
float hashUniform(uint a, uint b, uint c) {
  uint h = a * 747796405u + b * 2891336453u + c * 3266489917u + 0x9e3779b9u;
  h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
  h = (h >> 22u) ^ h;
  return float(h >> 8) * (1.0 / 16777216.0);
}
