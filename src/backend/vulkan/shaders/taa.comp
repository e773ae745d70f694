#version 450
// Pass "taa": temporal anti-aliasing with neighbourhood clamping (Karis 2014): the previous
// output, fetched bilinearly or with the 4x4 Catmull-Rom cubic (historyFilter; Jimenez's SMAA
// T2x) at the reprojected position, is clamped to the YCoCg min/max box of
// the current 3x3 neighbourhood (optionally averaged with the 5-tap cross's bounds, as the BMFR
// code) and blended, on linear radiance or on display-encoded values (Reinhard + gamma 2,
// decoded after). Port of src/passes/taa.cpp and taa_simd.cpp. The 3x3 neighbourhood is read
// through shared memory (an 18x18 tile per 16x16 workgroup: 1.27 loads per pixel instead of 9).
#include "common.glsl"
#include "reprojection.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Rp { uint rp[]; };
layout(std430, binding = 1) readonly buffer Color { float color[]; };
layout(std430, binding = 2) readonly buffer Hist { float hist[]; };
layout(std430, binding = 3) writeonly buffer Out { float outp[]; };        // next history
layout(std430, binding = 4) writeonly buffer Linear { float linearOut[]; };   // display: decoded output
layout(std430, binding = 5) readonly buffer Keys { uint keys[]; };            // keyed: surface keys (taa_keys.comp)

layout(push_constant) uniform PC {
  uint width, height;
  float alpha;
  uint valid;    // 0: first frame, output = input
  uint display;  // 1: clamp and blend taaEncode()d values (tonemap.h)
  float crossWeight;
  uint catmullRom;  // 1: 4x4 Catmull-Rom history fetch (TaaHistoryFilter)
  uint keyed;       // 1: the box over the pixel's own surface (TaaSettings::taaOwnSurface)
  uint rejection;   // 1: no history where the record accepted no tap (taaHistoryRejection)
  float subpixelAlpha;  // taaSubpixelAlpha
} pc;

vec3 toYCoCg(vec3 c) {
  precise vec3 r;
  r.x = 0.25 * c.r + 0.5 * c.g + 0.25 * c.b;
  r.y = 0.5 * c.r - 0.5 * c.b;
  r.z = -0.25 * c.r + 0.5 * c.g - 0.25 * c.b;
  return r;
}
vec3 fromYCoCg(vec3 c) {
  precise vec3 r;
  r.r = c.x + c.y - c.z;
  r.g = c.x + c.z;
  r.b = c.x - c.y - c.z;
  return r;
}

// tonemap::taaEncode / taaDecode (src/passes/tonemap.h).
const float kMaxEncoded = 1.0 - 1.0 / 2097152.0;
vec3 encode(vec3 x) {
  x = min(max(x, vec3(0.0)), vec3(1e30));  // NaN -> 0 on the CPU; inputs are sanitized here
  precise vec3 t = x / (1.0 + x);
  return sqrt(t);
}
vec3 decode(vec3 y) {
  y = clamp(y, vec3(0.0), vec3(kMaxEncoded));
  precise vec3 t = y * y;
  precise vec3 r = t / (1.0 - t);
  return r;
}

vec3 histAt(int x, int y, uint plane) {
  const uint j = uint(clamp(y, 0, int(pc.height) - 1)) * pc.width + uint(clamp(x, 0, int(pc.width) - 1));
  return vec3(hist[j], hist[plane + j], hist[2u * plane + j]);
}

// catmullRomWeights in taa_simd.cpp: Keys' a = -1/2 cubic for taps -1..2, |w| < 2^-24 -> 0.
vec4 catmullRomWeights(float t) {
  precise vec4 w;
  w.x = 0.5 * t * ((2.0 - t) * t - 1.0);
  w.y = 0.5 * (t * t * (3.0 * t - 5.0) + 2.0);
  w.z = 0.5 * t * ((4.0 - 3.0 * t) * t + 1.0);
  w.w = 0.5 * t * t * (t - 1.0);
  return mix(w, vec4(0.0), lessThan(abs(w), vec4(1.0 / 16777216.0)));
}

// catmullRomFetch in taa_simd.cpp: the separable 4x4 cubic, rows first, clamp-to-edge taps.
vec3 catmullRomHistory(float px, float py, uint plane) {
  const float fx = floor(px), fy = floor(py);
  const vec4 wx = catmullRomWeights(px - fx), wy = catmullRomWeights(py - fy);
  const int x0 = int(fx) - 1, y0 = int(fy) - 1;
  precise vec3 sum = vec3(0.0);
  for (int j = 0; j < 4; ++j) {
    precise vec3 r = wx.x * histAt(x0, y0 + j, plane) + wx.y * histAt(x0 + 1, y0 + j, plane) +
                     wx.z * histAt(x0 + 2, y0 + j, plane) + wx.w * histAt(x0 + 3, y0 + j, plane);
    sum += wy[j] * r;
  }
  return sum;
}

// The CPU's `consistent` (taa_simd.cpp): the reprojection record (reprojection.glsl) is
// bilinear and keeps every texel of the plain 2x2 footprint weighted above kTaaNegligibleTap
// (passes/taa_kernels.h), wherever a slide at the border put it in the record's footprint.
const float kTaaNegligibleTap = 1.0 / 256.0;
bool accepted(uint i, float px, float py, uint plane) {
  if ((rp[i] & 3u) != RP_BILINEAR) return false;
  const float fx = floor(px), fy = floor(py);
  precise float ax = px - fx, ay = py - fy;
  precise vec4 plain = vec4((1.0 - ax) * (1.0 - ay), ax * (1.0 - ay), (1.0 - ax) * ay, ax * ay);
  const int b = int(rp[plane + i]), bx = b % int(pc.width), by = b / int(pc.width);
  for (uint t = 0u; t < 4u; ++t) {
    if (!(plain[t] > kTaaNegligibleTap)) continue;
    const int dx = int(fx) + int(t & 1u) - bx, dy = int(fy) + int(t >> 1u) - by;
    if (dx < 0 || dx > 1 || dy < 0 || dy > 1 || !(uintBitsToFloat(rp[(2u + uint(dy * 2 + dx)) * plane + i]) > 0.0)) return false;
  }
  return true;
}

shared vec3 tile[18][18];
shared float tileMax[18][18];  // display: largest encoded channel
shared uint tileKey[18][18];   // keyed: surface keys

vec3 loadColor(ivec2 q, uint plane) {
  q = clamp(q, ivec2(0), ivec2(pc.width, pc.height) - 1);
  const uint j = uint(q.y) * pc.width + uint(q.x);
  return vec3(color[j], color[plane + j], color[2u * plane + j]);
}

void main() {
  const uint plane = pc.width * pc.height;
  const bool display = pc.display != 0u;
  const ivec2 origin = ivec2(gl_WorkGroupID.xy) * 16 - 1;
  for (uint k = gl_LocalInvocationIndex; k < 18u * 18u; k += 256u) {
    const ivec2 t = ivec2(k % 18u, k / 18u);
    vec3 c = loadColor(origin + t, plane);
    if (display) c = encode(c);
    tile[t.y][t.x] = toYCoCg(c);
    tileMax[t.y][t.x] = max(max(c.r, c.g), c.b);
    if (pc.keyed != 0u) {
      const ivec2 q = clamp(origin + t, ivec2(0), ivec2(pc.width, pc.height) - 1);
      tileKey[t.y][t.x] = keys[uint(q.y) * pc.width + uint(q.x)];
    }
  }
  barrier();

  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x;
  const vec3 c = vec3(color[i], color[plane + i], color[2u * plane + i]);
  if (pc.valid == 0u) {
    const vec3 e = display ? encode(c) : c;
    for (uint k = 0; k < 3; ++k) outp[k * plane + i] = e[k];
    if (display)
      for (uint k = 0; k < 3; ++k) linearOut[k * plane + i] = c[k];
    return;
  }
  const ivec2 l = ivec2(gl_LocalInvocationID.xy) + 1;
  const vec3 cur = tile[l.y][l.x];
  vec3 lo = cur, hi = cur;
  float top = 0.0;
  const bool keyed = pc.keyed != 0u;
  const uint own = keyed ? tileKey[l.y][l.x] : 0u;
  // Keyed: only the neighbours of the pixel's own key (the pixel itself always in: own == own).
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (keyed && tileKey[l.y + dy][l.x + dx] != own) continue;
      const vec3 n = tile[l.y + dy][l.x + dx];
      lo = min(lo, n);
      hi = max(hi, n);
      top = max(top, tileMax[l.y + dy][l.x + dx]);
    }
  vec3 crossLo = cur, crossHi = cur;
  for (int k = 0; k < 4; ++k) {
    const ivec2 d = k < 2 ? ivec2(2 * k - 1, 0) : ivec2(0, 2 * k - 5);
    if (keyed && tileKey[l.y + d.y][l.x + d.x] != own) continue;
    const vec3 n = tile[l.y + d.y][l.x + d.x];
    crossLo = min(crossLo, n);
    crossHi = max(crossHi, n);
  }
  precise vec3 bLo = lo + pc.crossWeight * (crossLo - lo);
  precise vec3 bHi = hi + pc.crossWeight * (crossHi - hi);
  precise float px = uintBitsToFloat(rp[6u * plane + i]) - 0.5, py = uintBitsToFloat(rp[7u * plane + i]) - 0.5;
  vec3 result = display ? encode(c) : c;
  const bool rejected = pc.rejection != 0u && (rp[i] & 3u) == RP_NONE;
  if (px > -1.0 && py > -1.0 && px < float(pc.width) && py < float(pc.height) && !rejected) {
    const int x0 = int(floor(px)), y0 = int(floor(py));
    precise float ax = px - float(x0), ay = py - float(y0);
    precise vec3 h = vec3(0.0);
    if (pc.catmullRom != 0u && accepted(i, px, py, plane)) h = catmullRomHistory(px, py, plane);
    else for (int t = 0; t < 4; ++t) {
      const int tx = clamp(x0 + (t & 1), 0, int(pc.width) - 1), ty = clamp(y0 + (t >> 1), 0, int(pc.height) - 1);
      precise float wt = ((t & 1) != 0 ? ax : 1.0 - ax) * ((t >> 1) != 0 ? ay : 1.0 - ay);
      const uint j = uint(ty) * pc.width + uint(tx);
      h += wt * vec3(hist[j], hist[plane + j], hist[2u * plane + j]);
    }
    vec3 hy = clamp(toYCoCg(h), bLo, bHi);
    // blendWeights (taa_simd.cpp): alpha rises with the fetch's subpixel offset.
    precise float fx = px - floor(px), fy = py - floor(py);
    precise float alpha = min(1.0, pc.alpha + pc.subpixelAlpha * (fx * (1.0 - fx) + fy * (1.0 - fy)));
    precise vec3 blended = alpha * cur + (1.0 - alpha) * hy;
    result = fromYCoCg(blended);
  }
  result = max(result, vec3(0.0));
  if (display) result = min(result, vec3(top));  // a box corner outside the RGB cube stays bounded
  for (uint k = 0; k < 3; ++k) outp[k * plane + i] = result[k];
  if (display) {
    const vec3 o = decode(result);
    for (uint k = 0; k < 3; ++k) linearOut[k * plane + i] = o[k];
  }
}
