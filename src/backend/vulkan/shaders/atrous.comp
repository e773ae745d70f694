#version 450
// Pass "atrousN": one level of the edge-avoiding a-trous wavelet filter (Dammertz et al. 2010)
// with SVGF's weights w = w_z w_n w_l and variance propagation Var' = sum h^2 w^2 Var / (sum h w)^2
// (Schied et al. 2017 Sec. 4.3, Eq. 3-5). Port of atrousLevel (src/passes/atrous.cpp).
// Images: 5 planes (R, G, B, luminance, variance). Taps outside the image weigh 0 (the CPU's
// zero border: normal 0 gives w_n = 0), and so does the variance prefilter's outside read.
// For steps 1 and 2 the taps are read from a shared-memory tile of the workgroup (16 + 4 step)^2
// (guide features, colour, luminance): one load per tile pixel instead of 25 per pixel.
// Variant atrous_masked (RTD_SAMPLE_MASK, AtrousLevel::validIn/validOut): sparse input (Dundr
// Sec. 5). A pixel is valid where plane `validPlane` of binding 7 is > 0 (the history length
// for the first level, the previous level's validity after it); invalid pixels weigh 0, the
// centre included; a pixel that receives any weight is valid in binding 8 and gets the
// normalized sum, one with none stays invalid with colour 0.
// Variants atrous_untiled / atrous_masked_untiled (RTD_UNTILED): the same without the shared
// tile, for devices with less than the tile's 18 KiB of shared memory (Vulkan guarantees 16).
// Variants atrous_glossy / atrous_glossy_untiled (RTD_GLOSSY, AtrousLevel::indirectDistance
// etc.): Gersthofer's glossy weights (Eq. 3.2): w_zi from the indirect ray length z_i (binding
// 7) and its factor 1 - roughness (binding 8), and w_r on the neighbours as 1/w_r on the centre
// (binding 9); dense input.
// variant: atrous_masked RTD_SAMPLE_MASK
// variant: atrous_untiled RTD_UNTILED
// variant: atrous_masked_untiled RTD_MASKED_UNTILED
// variant: atrous_glossy RTD_GLOSSY
// variant: atrous_glossy_untiled RTD_GLOSSY_UNTILED
#ifdef RTD_MASKED_UNTILED
#define RTD_SAMPLE_MASK
#define RTD_UNTILED
#endif
#ifdef RTD_GLOSSY_UNTILED
#define RTD_GLOSSY
#define RTD_UNTILED
#endif
#include "common.glsl"
#include "atrous.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Depth { float depth[]; };
layout(std430, binding = 1) readonly buffer Normal { float normal[]; };
layout(std430, binding = 2) readonly buffer Grad { float grad[]; };
layout(std430, binding = 3) readonly buffer In { float img[]; };
layout(std430, binding = 4) writeonly buffer Out { float outp[]; };
layout(std430, binding = 5) readonly buffer Scale { float sigmaScale[]; };
// Voorhuis Eq. 6 (AtrousLevel::spatialFalloff): every tap's weight times exp(-c(p) |k|^2), k
// the offset in kernel units.
layout(std430, binding = 6) readonly buffer Falloff { float falloff[]; };
#ifdef RTD_SAMPLE_MASK
layout(std430, binding = 7) readonly buffer ValidIn { float validIn[]; };
layout(std430, binding = 8) writeonly buffer ValidOut { float validOut[]; };
#endif
#ifdef RTD_GLOSSY
layout(std430, binding = 7) readonly buffer Zi { float zi[]; };
layout(std430, binding = 8) readonly buffer ZiScale { float ziScale[]; };
layout(std430, binding = 9) readonly buffer Centre { float centreScale[]; };
#endif

#define F_PREFILTER 1u
#define F_VARIANCE_SCALE 2u
#define F_SIGMA_SCALE 4u
#define F_PROPAGATE 8u
#define F_FALLOFF 16u
#define F_INDIRECT_DISTANCE 32u
#define F_CENTRE_SCALE 64u
#define F_KEY 128u
// AtrousLevel::surfaceKey: a tap whose key differs from the centre's weighs 0 (the last
// binding of each variant; a dummy without F_KEY).
#if defined(RTD_SAMPLE_MASK)
#define KEY_BINDING 9
#elif defined(RTD_GLOSSY)
#define KEY_BINDING 10
#else
#define KEY_BINDING 7
#endif
layout(std430, binding = KEY_BINDING) readonly buffer Key { float surfaceKey[]; };

layout(push_constant) uniform PC {
  uint width, height;
  int step, radius;  // radius 2: 5x5 B3 spline; 1: 3x3 binomial
  float sigmaDepth, depthEpsilon;
  int normalExponent;
  float sigmaLuminance, luminanceEpsilon;
  uint flags;
  uint luminanceMode;
  uint validPlane;  // atrous_masked: plane of binding 7 holding the input validity
  float depthEpsilonRelative;  // w_z's eps = depthEpsilon + depthEpsilonRelative |z(p)|
} pc;

float kernel1D(int d) {
  if (pc.radius == 2) return d == 0 ? 3.0 / 8.0 : (abs(d) == 1 ? 0.25 : 1.0 / 16.0);
  return d == 0 ? 0.5 : 0.25;
}

#ifndef RTD_UNTILED
// Shared tile for small steps: 16 + 2 * 2 * step <= 24 pixels a side (8 x 24^2 floats = 18 KiB;
// passes.cpp picks the untiled variant where the device has less).
const int kTile = 24;
shared float sZ[kTile * kTile], sNx[kTile * kTile], sNy[kTile * kTile], sNz[kTile * kTile];
shared float sR[kTile * kTile], sG[kTile * kTile], sB[kTile * kTile], sL[kTile * kTile];
#endif

void main() {
  const uint W = pc.width, H = pc.height, plane = W * H;
  const int reach = pc.radius * pc.step;
#ifdef RTD_UNTILED
  const bool tiled = false;
#else
  const bool tiled = 16 + 2 * reach <= kTile;
#endif
  const ivec2 origin = ivec2(gl_WorkGroupID.xy) * 16 - reach;
  const int side = 16 + 2 * reach;
#ifndef RTD_UNTILED
  if (tiled) {
    for (int k = int(gl_LocalInvocationIndex); k < side * side; k += 256) {
      const ivec2 q = origin + ivec2(k % side, k / side);
      if (q.x < 0 || q.y < 0 || q.x >= int(W) || q.y >= int(H)) {
        sNx[k] = 0.0; sNy[k] = 0.0; sNz[k] = 0.0;  // w_n = 0: the tap does not count
        sZ[k] = 0.0; sR[k] = 0.0; sG[k] = 0.0; sB[k] = 0.0; sL[k] = 0.0;
        continue;
      }
      const uint j = uint(q.y) * W + uint(q.x);
      sZ[k] = depth[j];
      sNx[k] = normal[j]; sNy[k] = normal[plane + j]; sNz[k] = normal[2u * plane + j];
#ifdef RTD_SAMPLE_MASK
      // An invalid tap weighs 0 like a tap outside the image: through w_n = 0.
      if (!(validIn[pc.validPlane * plane + j] > 0.0)) { sNx[k] = 0.0; sNy[k] = 0.0; sNz[k] = 0.0; }
#endif
      sR[k] = img[j]; sG[k] = img[plane + j]; sB[k] = img[2u * plane + j]; sL[k] = img[3u * plane + j];
    }
    barrier();
  }
#endif

  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, W, H)) return;
  const int x = int(p.x), y = int(p.y);
  const uint c = p.y * W + p.x;
  const float zc = depth[c];
  const vec3 n = vec3(normal[c], normal[plane + c], normal[2u * plane + c]);
  const float gx = grad[c] * pc.sigmaDepth, gy = grad[plane + c] * pc.sigmaDepth;
  const float epsZ = pc.depthEpsilon + pc.depthEpsilonRelative * abs(zc);
  const float lc = img[3u * plane + c];

  // w_l bandwidth from the (3x3-Gaussian-prefiltered, Eq. 5) variance at the centre.
  float v = img[4u * plane + c];
  if ((pc.flags & F_PREFILTER) != 0u) {
    float s4 = 0.0, sd = 0.0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const int qx = x + dx, qy = y + dy;
        if (qx < 0 || qy < 0 || qx >= int(W) || qy >= int(H)) continue;  // zero border
        const float vq = img[4u * plane + uint(qy) * W + uint(qx)];
        if (dx == 0 || dy == 0) s4 += vq; else sd += vq;
      }
    v = 0.25 * v + 0.125 * s4 + 0.0625 * sd;
  }
  v = max(v, 0.0);
  const float sdev = (pc.flags & F_VARIANCE_SCALE) != 0u ? v : sqrt(v);
  const float k = (pc.flags & F_SIGMA_SCALE) != 0u ? sigmaScale[c] : 1.0;
  const float inv = k > 0.0 ? 1.0 / (pc.sigmaLuminance * k * sdev + pc.luminanceEpsilon) : 0.0;
#ifdef RTD_GLOSSY
  // Eq. 3.2: (1 - roughness(p)) / (sqrt(g3x3(Var)) + eps), one factor for every tap.
  const bool distance = (pc.flags & F_INDIRECT_DISTANCE) != 0u;
  const float ziInv = distance ? ziScale[c] / (sqrt(v) + pc.luminanceEpsilon) : 0.0;
  const float zic = distance ? zi[c] : 0.0;
#endif

  const bool propagate = (pc.flags & F_PROPAGATE) != 0u;
  const float fall = (pc.flags & F_FALLOFF) != 0u ? falloff[c] : 0.0;
  const bool keyed = (pc.flags & F_KEY) != 0u;
  const float keyc = keyed ? surfaceKey[c] : 0.0;
#ifdef RTD_SAMPLE_MASK
  const float h0 = validIn[pc.validPlane * plane + c] > 0.0 ? kernel1D(0) * kernel1D(0) : 0.0;
#else
  float h0 = kernel1D(0) * kernel1D(0);
#endif
#ifdef RTD_GLOSSY
  if ((pc.flags & F_CENTRE_SCALE) != 0u) h0 *= centreScale[c];  // w_r on every neighbour
#endif
  float sw = h0, sv = propagate ? h0 * h0 * img[4u * plane + c] : 0.0;
  vec3 sc = h0 * vec3(img[c], img[plane + c], img[2u * plane + c]);
  for (int dy = -pc.radius; dy <= pc.radius; ++dy)
    for (int dx = -pc.radius; dx <= pc.radius; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const int ox = dx * pc.step, oy = dy * pc.step;
      const int qx = x + ox, qy = y + oy;
      if (qx < 0 || qy < 0 || qx >= int(W) || qy >= int(H)) continue;
      const uint q = uint(qy) * W + uint(qx);
      if (keyed && surfaceKey[q] != keyc) continue;
      float zq, lq;
      vec3 nq, cq;
#ifndef RTD_UNTILED
      if (tiled) {
        const int t = (qy - origin.y) * side + (qx - origin.x);
        zq = sZ[t]; nq = vec3(sNx[t], sNy[t], sNz[t]); cq = vec3(sR[t], sG[t], sB[t]); lq = sL[t];
      } else
#endif
      {
#ifdef RTD_SAMPLE_MASK
        if (!(validIn[pc.validPlane * plane + q] > 0.0)) continue;
#endif
        zq = depth[q];
        nq = vec3(normal[q], normal[plane + q], normal[2u * plane + q]);
        cq = vec3(img[q], img[plane + q], img[2u * plane + q]);
        lq = img[3u * plane + q];
      }
      const float wn = normalWeight(dot(n, nq), pc.normalExponent);
      const float denomZ = abs(gx * float(ox) + gy * float(oy)) + epsZ;
#ifdef RTD_GLOSSY
      const float expo = abs(zc - zq) / denomZ + abs(lc - lq) * inv + fall * float(dx * dx + dy * dy) +
                         (distance ? abs(zic - zi[q]) * ziInv : 0.0);
#else
      const float expo = abs(zc - zq) / denomZ + abs(lc - lq) * inv + fall * float(dx * dx + dy * dy);
#endif
      const float wt = cutWeight(kernel1D(dx) * kernel1D(dy) * wn * exp(-expo));  // h w, cut as a whole
      sw += wt;
      sc += wt * cq;
      if (propagate) sv += wt * wt * img[4u * plane + q];
    }
#ifdef RTD_SAMPLE_MASK
  const bool any = sw > 0.0;
  const float rcp = any ? 1.0 / sw : 0.0;
  validOut[c] = any ? 1.0 : 0.0;
#else
  const float rcp = 1.0 / sw;
#endif
  const vec3 r = sc * rcp;
  outp[c] = r.r;
  outp[plane + c] = r.g;
  outp[2u * plane + c] = r.b;
  outp[3u * plane + c] = momentLuminance(pc.luminanceMode, r);
  // Without propagation the next level sees this level's input variance, as the CPU's swap does.
  outp[4u * plane + c] = propagate ? sv * rcp * rcp : img[4u * plane + c];
}
