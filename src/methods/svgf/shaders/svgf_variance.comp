#version 450
// Pass "variance" of SVGF (Schied et al. 2017 Sec. 4.2): level-0 input of the a-trous filter.
// Colour = accumulated colour, luminance of it, variance = max(0, mu2 - mu1^2) where the history
// length n >= shortHistoryFrames; shorter histories (spatialEstimate) take the depth/normal-
// weighted window estimate E_w[l^2] - E_w[l]^2 of the current luminance (or, Voorhuis Sec. 6,
// of the accumulated moments). Also writes the per-pixel multiplier of sigma_l: 0 where w_l is
// off (Dundr), 8 - min(7, h) (Voorhuis Eq. 8), else 1. Port of svgf::estimateVariance and
// svgf::luminanceSigmaScale. Gersthofer Sec. 3.4.3: F_OBJECT_ID adds the mesh-id term.
#include "common.glsl"
#include "atrous.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Depth { float depth[]; };
layout(std430, binding = 1) readonly buffer Normal { float normal[]; };
layout(std430, binding = 2) readonly buffer Grad { float grad[]; };
layout(std430, binding = 3) readonly buffer Acc { float acc[]; };      // R, G, B, m1, m2, length
layout(std430, binding = 4) readonly buffer Cur { float cur[]; };      // this frame, demodulated
layout(std430, binding = 5) writeonly buffer Out { float outp[]; };    // R, G, B, lum, var
layout(std430, binding = 6) writeonly buffer Scale { float sigmaScale[]; };
layout(std430, binding = 7) readonly buffer Ids { float objectId[]; };  // F_OBJECT_ID (Gersthofer)

#define F_SPATIAL 1u
#define F_FROM_MOMENTS 2u
#define F_DISABLE_LUMINANCE_WEIGHT 4u
#define F_SHORT_HISTORY_BANDWIDTH 8u
#define F_OBJECT_ID 16u  // the spatial estimate also rejects neighbours of another object id

layout(push_constant) uniform PC {
  uint width, height;
  float shortHistoryFrames;
  int radius;
  float sigmaDepth, depthEpsilon;
  int normalExponent;
  uint luminanceMode;
  uint flags;
  float depthEpsilonRelative;  // w_z's eps = depthEpsilon + depthEpsilonRelative |z(p)|
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint W = pc.width, H = pc.height, plane = W * H;
  const uint i = p.y * W + p.x;
  const vec3 a = vec3(acc[i], acc[plane + i], acc[2u * plane + i]);
  const float m1 = acc[3u * plane + i], m2 = acc[4u * plane + i], len = acc[5u * plane + i];
  for (uint c = 0; c < 3; ++c) outp[c * plane + i] = a[c];
  outp[3u * plane + i] = momentLuminance(pc.luminanceMode, a);

  float var;
  if ((pc.flags & F_SPATIAL) == 0u || len >= pc.shortHistoryFrames) {
    var = max(0.0, m2 - m1 * m1);
  } else {
    const int x = int(p.x), y = int(p.y);
    const float zc = depth[i], gx = grad[i], gy = grad[plane + i];
    const float epsZ = pc.depthEpsilon + pc.depthEpsilonRelative * abs(zc);
    const vec3 n = vec3(normal[i], normal[plane + i], normal[2u * plane + i]);
    float sw = 0.0, s1 = 0.0, s2 = 0.0;
    for (int dy = -pc.radius; dy <= pc.radius; ++dy)
      for (int dx = -pc.radius; dx <= pc.radius; ++dx) {
        const int qx = x + dx, qy = y + dy;
        if (qx < 0 || qy < 0 || qx >= int(W) || qy >= int(H)) continue;  // zero border: weight 0
        const uint q = uint(qy) * W + uint(qx);
        float wt = 1.0;
        if (dx != 0 || dy != 0) {
          const vec3 nq = vec3(normal[q], normal[plane + q], normal[2u * plane + q]);
          const float wz = exp(-abs(zc - depth[q]) / (pc.sigmaDepth * abs(gx * float(dx) + gy * float(dy)) + epsZ));
          wt = cutWeight(normalWeight(dot(n, nq), pc.normalExponent) * wz);
          if ((pc.flags & F_OBJECT_ID) != 0u && objectId[q] != objectId[i]) wt = 0.0;
          if (!(wt > 0.0)) continue;
        }
        float l1, l2;
        if ((pc.flags & F_FROM_MOMENTS) != 0u) {
          l1 = acc[3u * plane + q];
          l2 = acc[4u * plane + q];
        } else {
          l1 = momentLuminance(pc.luminanceMode, vec3(cur[q], cur[plane + q], cur[2u * plane + q]));
          l2 = l1 * l1;
        }
        sw += wt;
        s1 += wt * l1;
        s2 += wt * l2;
      }
    s1 /= sw;
    s2 /= sw;
    var = max(0.0, s2 - s1 * s1);
  }
  outp[4u * plane + i] = var;

  float k = 1.0;
  if ((pc.flags & F_DISABLE_LUMINANCE_WEIGHT) != 0u && len < pc.shortHistoryFrames) k = 0.0;
  else if ((pc.flags & F_SHORT_HISTORY_BANDWIDTH) != 0u) k = float(8 - min(7, max(0, int(len) - 1)));
  sigmaScale[i] = k;
}
