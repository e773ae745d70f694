#version 450
// Pass "reflections" (specular reprojection): the primary reprojection record, with every
// specular pixel redone (Voorhuis 2018 Sec. 4): mode 1 (NoSpecReproj) no history and an
// off-screen position (no TAA); mode 2 mirror pixels (class 3) and glossy pixels below the
// reflection threshold (class 2) search the previous frame by diamond search (Algorithm 1,
// Eq. 1 on the reflected position / Eq. 5 on the representative rays) and reproject bilinearly
// at the match onto previous pixels of their class (mirrors: with agreeing reflected normals).
// Port of specularReprojection (src/passes/reflection_reprojection.cpp).
#include "common.glsl"
#include "diamond_search.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Primary { uint primary[]; };
layout(std430, binding = 1) writeonly buffer Rp { uint rp[]; };
layout(std430, binding = 2) readonly buffer Cls { float cls[]; };
layout(std430, binding = 3) readonly buffer PrevCls { float prevCls[]; };
layout(std430, binding = 4) readonly buffer CurRefl { float curRefl[]; };
layout(std430, binding = 5) readonly buffer CurReflN { float curReflN[]; };
layout(std430, binding = 6) readonly buffer PrevRefl { float prevRefl[]; };
layout(std430, binding = 7) readonly buffer PrevReflN { float prevReflN[]; };
layout(std430, binding = 8) readonly buffer CurPos { float curPos[]; };
layout(std430, binding = 9) readonly buffer CurDir { float curDir[]; };
layout(std430, binding = 10) readonly buffer CurDepth2 { float curDepth2[]; };
layout(std430, binding = 11) readonly buffer PrevPos { float prevPos[]; };
layout(std430, binding = 12) readonly buffer PrevDir { float prevDir[]; };
layout(std430, binding = 13) readonly buffer PrevDepth2 { float prevDepth2[]; };

#define F_MIRRORS 1u           // search mirror pixels
#define F_GLOSSY 2u            // search glossy pixels
#define F_REFLECTED_NORMAL 4u  // the frames have ReflectedNormal
#define F_SKY_DIRECTION 8u     // the frames have MirrorDirection and Position (mirrors showing the sky)
#define F_SCALE_LDSP 16u
#define F_SUBPIXEL 32u
#define F_QUADRATIC 64u  // SubpixelFit::quadratic

layout(push_constant) uniform PC {
  uint width, height;
  uint mode;  // 0 primary (a copy), 1 none, 2 reflection
  uint flags;
  int maxIterations;
  float normalTolerance;
} pc;

const float kMirror = 3.0, kGlossyReflection = 2.0;

bool has(uint f) { return (pc.flags & f) != 0u; }
uint planeSize() { return pc.width * pc.height; }

// Mirror world feature (MirrorFeature on the CPU): the reflected position, or for a mirror
// showing the sky (zero reflected normal) the point kMissDepth along its mirror direction.
bool skyCur(uint i) {
  const uint n = planeSize();
  precise float l = curReflN[i] * curReflN[i] + curReflN[n + i] * curReflN[n + i] + curReflN[2u * n + i] * curReflN[2u * n + i];
  return has(F_REFLECTED_NORMAL) && l < 0.25;
}
bool skyPrev(uint j) {
  const uint n = planeSize();
  precise float l = prevReflN[j] * prevReflN[j] + prevReflN[n + j] * prevReflN[n + j] + prevReflN[2u * n + j] * prevReflN[2u * n + j];
  return has(F_REFLECTED_NORMAL) && l < 0.25;
}
vec3 skyPoint(vec3 o, vec3 d) {
  precise float len2 = d.x * d.x + d.y * d.y + d.z * d.z;
  const float len = sqrt(len2);
  precise float s = len > 0.0 ? kMissDepth / len : 0.0;
  precise vec3 r;
  r.x = o.x + d.x * s;
  r.y = o.y + d.y * s;
  r.z = o.z + d.z * s;
  return r;
}
vec3 load3(uint i, uint which) {  // 0 cur refl, 1 prev refl, 2 cur pos, 3 cur dir, 4 prev pos, 5 prev dir
  const uint n = planeSize();
  if (which == 0u) return vec3(curRefl[i], curRefl[n + i], curRefl[2u * n + i]);
  if (which == 1u) return vec3(prevRefl[i], prevRefl[n + i], prevRefl[2u * n + i]);
  if (which == 2u) return vec3(curPos[i], curPos[n + i], curPos[2u * n + i]);
  if (which == 3u) return vec3(curDir[i], curDir[n + i], curDir[2u * n + i]);
  if (which == 4u) return vec3(prevPos[i], prevPos[n + i], prevPos[2u * n + i]);
  return vec3(prevDir[i], prevDir[n + i], prevDir[2u * n + i]);
}
vec3 mirrorFeatureCur(uint i) {
  if (skyCur(i) && has(F_SKY_DIRECTION)) return skyPoint(load3(i, 2u), load3(i, 3u));
  return load3(i, 0u);
}
vec3 mirrorFeaturePrev(uint j) {
  if (skyPrev(j) && has(F_SKY_DIRECTION)) return skyPoint(load3(j, 4u), load3(j, 5u));
  return load3(j, 1u);
}
// The representative ray: unit mirror direction, depth kMissDepth where the sample escaped.
void representativeRay(bool previous, uint i, out vec3 o, out vec3 d, out float depth) {
  o = load3(i, previous ? 4u : 2u);
  const vec3 dir = load3(i, previous ? 5u : 3u);
  precise float len2 = dir.x * dir.x + dir.y * dir.y + dir.z * dir.z;
  const float inv = len2 > 0.0 ? 1.0 / sqrt(len2) : 0.0;
  d = dir * inv;
  const float t = previous ? prevDepth2[i] : curDepth2[i];
  depth = t > 0.0 ? t : kMissDepth;
}

// The current pixel of the search.
bool gMirror;
vec3 gWorld, gO, gD;
float gDepth;

float searchDistance(int qx, int qy) {
  const uint j = uint(qy) * pc.width + uint(qx);
  if (gMirror) {
    if (prevCls[j] != kMirror) return kNoMatch;
    return worldDistance(gWorld, mirrorFeaturePrev(j));
  }
  if (prevCls[j] != kGlossyReflection) return kNoMatch;
  vec3 o, d;
  float depth;
  representativeRay(true, j, o, d, depth);
  return glossyDistance(gO, gD, gDepth, o, d, depth);
}
#define DS_WIDTH pc.width
#define DS_HEIGHT pc.height
#define DS_SEARCH
#include "diamond_search.glsl"

uint gPixel;
bool bilinearTapValid(int tx, int ty) {
  const uint j = uint(ty) * pc.width + uint(tx);
  if (prevCls[j] != (gMirror ? kMirror : kGlossyReflection)) return false;
  if (!gMirror || !has(F_REFLECTED_NORMAL)) return true;
  const bool a = skyCur(gPixel), b = skyPrev(j);
  if (a || b) return a == b;
  const uint n = planeSize(), i = gPixel;
  precise float dn = curReflN[i] * prevReflN[j] + curReflN[n + i] * prevReflN[n + j] + curReflN[2u * n + i] * prevReflN[2u * n + j];
  return dn >= pc.normalTolerance;
}
#define RP_BILINEAR_RECORD
#include "reprojection.glsl"

void store(uint i, uint kindMask, int base, vec4 wt, float px, float py) {
  const uint plane = planeSize();
  rp[i] = kindMask;
  rp[plane + i] = uint(base);
  for (uint t = 0; t < 4; ++t) rp[(2u + t) * plane + i] = floatBitsToUint(wt[t]);
  rp[6u * plane + i] = floatBitsToUint(px);
  rp[7u * plane + i] = floatBitsToUint(py);
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint plane = planeSize(), i = p.y * pc.width + p.x;
  const float c = cls[i];
  const bool mirror = c == kMirror && has(F_MIRRORS), glossy = c == kGlossyReflection && has(F_GLOSSY);
  if (pc.mode == 0u || c == 0.0 || (pc.mode == 2u && !mirror && !glossy)) {
    for (uint k = 0; k < 8u; ++k) rp[k * plane + i] = primary[k * plane + i];  // the primary record
    return;
  }
  if (pc.mode == 1u) {  // no history, no TAA
    store(i, RP_NONE, 0, vec4(0.0), -1e6, -1e6);
    return;
  }
  gMirror = mirror;
  gPixel = i;
  if (mirror) {
    gWorld = mirrorFeatureCur(i);
  } else {
    representativeRay(false, i, gO, gD, gDepth);
  }
  const vec2 start = vec2(uintBitsToFloat(primary[6u * plane + i]), uintBitsToFloat(primary[7u * plane + i]));
  const SearchResult r = diamondSearch(ivec2(p), start, has(F_SCALE_LDSP), pc.maxIterations, has(F_SUBPIXEL), has(F_QUADRATIC));
  if (r.best.x < 0) {
    store(i, RP_NONE, 0, vec4(0.0), -1e6, -1e6);
    return;
  }
  int base;
  vec4 wt;
  if (bilinearRecord(r.match.x, r.match.y, pc.width, pc.height, base, wt)) store(i, RP_BILINEAR, base, wt, r.match.x, r.match.y);
  else store(i, RP_NONE, 0, vec4(0.0), r.match.x, r.match.y);
}
