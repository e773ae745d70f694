#version 450
// Pass "reproject": where each pixel's history comes from (Schied et al. 2017 Sec. 4.1;
// Higginson Sec. 1.3.1, Eq. 1.4): the bilinear taps around the reprojected position that pass
// the depth, normal, object-id and position tests, renormalized; else the valid taps of the
// 3x3 neighbourhood with the Gaussian of Eq. 1.4. Port of src/passes/reprojection.cpp.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer CurDepth { float curDepth[]; };
layout(std430, binding = 1) readonly buffer PrevDepth { float prevDepth[]; };
layout(std430, binding = 2) readonly buffer CurNormal { float curNormal[]; };
layout(std430, binding = 3) readonly buffer PrevNormal { float prevNormal[]; };
layout(std430, binding = 4) readonly buffer CurId { float curId[]; };
layout(std430, binding = 5) readonly buffer PrevId { float prevId[]; };
layout(std430, binding = 6) readonly buffer CurPos { float curPos[]; };
layout(std430, binding = 7) readonly buffer PrevPos { float prevPos[]; };
layout(std430, binding = 8) readonly buffer Motion { float motion[]; };
layout(std430, binding = 9) readonly buffer DepthGrad { float depthGrad[]; };
// Previous camera: worldToCamera then projection, row-major (rtd::Camera).
layout(std430, binding = 10) readonly buffer PrevCamera { float prevCamera[]; };
layout(std430, binding = 11) writeonly buffer Rp { uint rp[]; };
// Current camera, same layout (for the view direction of pixels without geometry).
layout(std430, binding = 12) readonly buffer CurCamera { float curCamera[]; };

#define F_PREVIOUS 1u
#define F_DEPTH 2u
#define F_NORMAL 4u
#define F_ID 8u
#define F_POSITION 16u
#define F_MOTION 32u
#define F_FROM_CAMERA 64u
#define F_DEPTH_GRADIENT 128u
#define F_FALLBACK 256u
#define F_SKY 512u  // with F_FROM_CAMERA: pixels with a zero normal reproject their view direction

layout(push_constant) uniform PC {
  uint width, height, flags;
  float depthTolerance, depthGradientScale, normalTolerance, positionTolerance, positionFootprints;
} pc;

bool has(uint f) { return (pc.flags & f) != 0u; }

float depthSlope(int x, int y, uint plane) {
  const uint w = pc.width;
  if (has(F_DEPTH_GRADIENT)) {
    const uint i = uint(y) * w + uint(x);
    return max(abs(depthGrad[i]), abs(depthGrad[plane + i]));
  }
  const float c = curDepth[uint(y) * w + uint(x)];
  const int W = int(pc.width), H = int(pc.height);
  const float l = curDepth[uint(y) * w + uint(max(x - 1, 0))], r = curDepth[uint(y) * w + uint(min(x + 1, W - 1))];
  const float u = curDepth[uint(max(y - 1, 0)) * w + uint(x)], d = curDepth[uint(min(y + 1, H - 1)) * w + uint(x)];
  const float gx = min(abs(l - c), abs(r - c)), gy = min(abs(u - c), abs(d - c));
  return max(gx, gy);
}

// Squared position tolerance of pixel (x, y): positionTolerance + positionFootprints times its
// world-space footprint (TapTest::positionTolerance2 in src/passes/reprojection_simd.cpp).
float positionTolerance2(int x, int y, uint plane) {
  const int W = int(pc.width), H = int(pc.height);
  const uint i = uint(y) * pc.width + uint(x);
  const vec3 c = vec3(curPos[i], curPos[plane + i], curPos[2u * plane + i]);
  const int l = clamp(x > 0 ? x - 1 : x + 1, 0, W - 1), r = clamp(x < W - 1 ? x + 1 : x - 1, 0, W - 1);
  const int u = clamp(y > 0 ? y - 1 : y + 1, 0, H - 1), d = clamp(y < H - 1 ? y + 1 : y - 1, 0, H - 1);
  const uint js[4] = uint[4](uint(y) * pc.width + uint(l), uint(y) * pc.width + uint(r), uint(u) * pc.width + uint(x),
                             uint(d) * pc.width + uint(x));
  float d2[4];
  for (int k = 0; k < 4; ++k) {
    const uint j = js[k];
    precise vec3 e = vec3(curPos[j], curPos[plane + j], curPos[2u * plane + j]) - c;
    precise float s = e.x * e.x + e.y * e.y + e.z * e.z;
    d2[k] = s;
  }
  const float f2 = max(min(d2[0], d2[1]), min(d2[2], d2[3]));
  precise float tol = pc.positionTolerance + pc.positionFootprints * sqrt(f2);
  precise float tol2 = tol * tol;
  return tol2;
}
float gPositionTol2;

bool tapValid(uint i, int px, int py, float depthTol, uint plane) {
  if (px < 0 || py < 0 || px >= int(pc.width) || py >= int(pc.height)) return false;
  const uint j = uint(py) * pc.width + uint(px);
  if (has(F_DEPTH)) {
    const float z = curDepth[i], zp = prevDepth[j];
    if (!(abs(zp - z) <= depthTol)) return false;
  }
  if (has(F_NORMAL)) {
    const vec3 n = vec3(curNormal[i], curNormal[plane + i], curNormal[2u * plane + i]);
    const vec3 np = vec3(prevNormal[j], prevNormal[plane + j], prevNormal[2u * plane + j]);
    precise float n2 = n.x * n.x + n.y * n.y + n.z * n.z;
    if (n2 < 0.25) {
      // Background (zero normal: a miss) matches background only.
      precise float np2 = np.x * np.x + np.y * np.y + np.z * np.z;
      if (!(np2 < 0.25)) return false;
    } else {
      precise float d = n.x * np.x + n.y * np.y + n.z * np.z;
      if (!(d >= pc.normalTolerance)) return false;
    }
  }
  if (has(F_ID) && curId[i] != prevId[j]) return false;
  if (has(F_POSITION)) {
    precise float d2 = 0.0;
    for (uint c = 0; c < 3; ++c) {
      precise float d = curPos[c * plane + i] - prevPos[c * plane + j];
      d2 += d * d;
    }
    if (!(d2 <= gPositionTol2)) return false;
  }
  return true;
}

// The pixel whose taps bilinearRecord tests.
uint gPixel;
float gDepthTol;
bool bilinearTapValid(int tx, int ty) { return tapValid(gPixel, tx, ty, gDepthTol, pc.width * pc.height); }
#define RP_BILINEAR_RECORD
#include "reprojection.glsl"

// Row-major 4x4 (at element m of prevCamera) times (x, y, z, 1), without contraction.
vec4 transformPoint(uint m, vec3 p) {
  precise vec4 r;
  for (uint k = 0; k < 4; ++k)
    r[k] = prevCamera[m + k * 4] * p.x + prevCamera[m + k * 4 + 1] * p.y + prevCamera[m + k * 4 + 2] * p.z +
           prevCamera[m + k * 4 + 3];
  return r;
}

// Row r of directionToClip (src/passes/reprojection.h): (projection x worldToCamera)[r, 0:3].
vec3 curDirectionRow(uint r) {
  vec3 a = vec3(0.0);
  for (uint j = 0; j < 3; ++j) a += curCamera[16 + r * 4 + j] * vec3(curCamera[j * 4], curCamera[j * 4 + 1], curCamera[j * 4 + 2]);
  return a;
}
vec3 prevDirectionRow(uint r) {
  vec3 a = vec3(0.0);
  for (uint j = 0; j < 3; ++j) a += prevCamera[16 + r * 4 + j] * vec3(prevCamera[j * 4], prevCamera[j * 4 + 1], prevCamera[j * 4 + 2]);
  return a;
}

// reprojectDirection (src/passes/reprojection.h): the previous position of the point at
// infinity seen through (sx, sy).
bool reprojectDirection(float sx, float sy, out float px, out float py) {
  const float nx = 2.0 * sx / float(pc.width) - 1.0, ny = 1.0 - 2.0 * sy / float(pc.height);
  const vec3 aw = curDirectionRow(3u);
  vec3 d = cross(curDirectionRow(0u) - nx * aw, curDirectionRow(1u) - ny * aw);
  const float cw = dot(aw, d);
  if (!(abs(cw) > 0.0)) return false;
  if (cw < 0.0) d = -d;
  const vec4 c = vec4(dot(prevDirectionRow(0u), d), dot(prevDirectionRow(1u), d), 0.0, dot(prevDirectionRow(3u), d));
  if (!(c.w > 0.0)) return false;
  px = (c.x / c.w * 0.5 + 0.5) * float(pc.width);
  py = (0.5 - c.y / c.w * 0.5) * float(pc.height);
  return true;
}

void store(uint i, uint plane, uint kindMask, int base, vec4 wt, float px, float py) {
  rp[i] = kindMask;
  rp[plane + i] = uint(base);
  for (uint t = 0; t < 4; ++t) rp[(2u + t) * plane + i] = floatBitsToUint(wt[t]);
  rp[6u * plane + i] = floatBitsToUint(px);
  rp[7u * plane + i] = floatBitsToUint(py);
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const int x = int(p.x), y = int(p.y);
  const uint w = pc.width, plane = pc.width * pc.height;
  const uint i = p.y * w + p.x;
  precise float px = float(x) + 0.5, py = float(y) + 0.5;
  if (!has(F_PREVIOUS)) {
    store(i, plane, RP_NONE, 0, vec4(0.0), px, py);
    return;
  }
  if (has(F_MOTION)) {
    px += motion[i];
    py += motion[plane + i];
  } else if (has(F_SKY) && dot(vec3(curNormal[i], curNormal[plane + i], curNormal[2u * plane + i]),
                                vec3(curNormal[i], curNormal[plane + i], curNormal[2u * plane + i])) < 0.25) {
    float sx = px, sy = py;
    if (!reprojectDirection(sx, sy, px, py)) {
      px = -1e6;
      py = -1e6;
    }
  } else if (has(F_FROM_CAMERA)) {
    const vec3 pos = vec3(curPos[i], curPos[plane + i], curPos[2u * plane + i]);
    const vec4 v = transformPoint(0u, pos);
    const vec4 c = transformPoint(16u, v.xyz);
    if (c.w > 0.0) {
      precise float nx = c.x / c.w * 0.5 + 0.5, ny = 0.5 - c.y / c.w * 0.5;
      px = nx * float(pc.width);
      py = ny * float(pc.height);  // NDC y is up, rows go down
    } else {
      px = -1e6;  // behind the previous camera
      py = -1e6;
    }
  }

  precise float depthTol = 0.0;
  if (has(F_DEPTH)) {
    precise float a = pc.depthTolerance * curDepth[i];
    precise float b = pc.depthGradientScale * depthSlope(x, y, plane);
    depthTol = a + b;
  }
  if (!(abs(px - 0.5) < 1e6 && abs(py - 0.5) < 1e6)) {
    store(i, plane, RP_NONE, 0, vec4(0.0), px, py);
    return;
  }
  gPixel = i;
  gDepthTol = depthTol;
  gPositionTol2 = has(F_POSITION) ? positionTolerance2(x, y, plane) : 0.0;
  int base;
  vec4 wt;
  if (bilinearRecord(px, py, pc.width, pc.height, base, wt)) {
    store(i, plane, RP_BILINEAR, base, wt, px, py);
    return;
  }
  if (has(F_FALLBACK)) {
    const int cx = int(floor(px)), cy = int(floor(py));
    uint mask = 0u;
    for (int t = 0; t < 9; ++t)
      if (tapValid(i, cx + t % 3 - 1, cy + t / 3 - 1, depthTol, plane)) mask |= 1u << t;
    if (mask != 0u) {
      store(i, plane, RP_FALLBACK | (mask << 2), cy * int(w) + cx, vec4(0.0), px, py);
      return;
    }
  }
  store(i, plane, RP_NONE, 0, vec4(0.0), px, py);
}
