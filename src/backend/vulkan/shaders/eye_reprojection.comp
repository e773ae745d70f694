#version 450
// Pass "eyeReprojection" (Gersthofer Sec. 3.4.2): each pixel of the target eye is carried into
// the source eye by its world position and the source's view-projection; the source's 2x2
// bilinear taps around the landing point are validated (normal angle, object id, the point's
// depth against the source's depth, source data present), the valid weights renormalized, and
// out = (1 - blend) target + blend * gather(source) where any tap is valid, target elsewhere.
// Port of eyeTaps / eyeReproject (src/passes/eye_reprojection.cpp), same order of operations.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer TPos { float tPos[]; };
layout(std430, binding = 1) readonly buffer TNormal { float tNormal[]; };
layout(std430, binding = 2) readonly buffer TId { float tId[]; };
layout(std430, binding = 3) readonly buffer SNormal { float sNormal[]; };
layout(std430, binding = 4) readonly buffer SDepth { float sDepth[]; };
layout(std430, binding = 5) readonly buffer SId { float sId[]; };
layout(std430, binding = 6) readonly buffer SGrad { float sGrad[]; };
layout(std430, binding = 7) readonly buffer SValid { float sValid[]; };  // plane validPlane > 0: data
// Source camera: worldToCamera then projection, row-major (rtd::Camera).
layout(std430, binding = 8) readonly buffer SCamera { float cam[]; };
layout(std430, binding = 9) readonly buffer TLight { float tLight[]; };
layout(std430, binding = 10) readonly buffer SLight { float sLight[]; };
layout(std430, binding = 11) writeonly buffer Out { float outp[]; };

#define F_ID 1u        // both eyes have object ids and testObjectId
#define F_DEPTH 2u     // testDepth
#define F_GRADIENT 4u  // the source has a depth gradient
#define F_VALID 8u     // sValid is bound

layout(push_constant) uniform PC {
  uint width, height, flags, validPlane;
  float normalTolerance, depthTolerance, depthGradientScale, blend;
} pc;

bool has(uint f) { return (pc.flags & f) != 0u; }

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint W = pc.width, H = pc.height, plane = W * H, i = p.y * W + p.x;
  const vec3 a = vec3(tLight[i], tLight[plane + i], tLight[2u * plane + i]);
  const vec3 n = vec3(tNormal[i], tNormal[plane + i], tNormal[2u * plane + i]);
  uint count = 0u;
  uint index[4];
  float weight[4];
  precise float sum = 0.0;
  if (!(n.x * n.x + n.y * n.y + n.z * n.z < 0.25)) {
    const vec3 pos = vec3(tPos[i], tPos[plane + i], tPos[2u * plane + i]);
    precise vec4 v, c;
    for (uint r = 0; r < 4; ++r) v[r] = cam[r * 4] * pos.x + cam[r * 4 + 1] * pos.y + cam[r * 4 + 2] * pos.z + cam[r * 4 + 3];
    for (uint r = 0; r < 4; ++r)
      c[r] = cam[16 + r * 4] * v.x + cam[16 + r * 4 + 1] * v.y + cam[16 + r * 4 + 2] * v.z + cam[16 + r * 4 + 3] * v.w;
    if (c.w > 0.0) {
      precise float px = (c.x / c.w * 0.5 + 0.5) * float(W);
      precise float py = (0.5 - c.y / c.w * 0.5) * float(H);
      const float z = -v.z;
      if (abs(px) < 1e6 && abs(py) < 1e6) {
        const float fx = px - 0.5, fy = py - 0.5;
        const int x0 = int(floor(fx)), y0 = int(floor(fy));
        const float ax = fx - float(x0), ay = fy - float(y0);
        const float bw[4] = float[4]((1.0 - ax) * (1.0 - ay), ax * (1.0 - ay), (1.0 - ax) * ay, ax * ay);
        const float id = tId[i];
        for (int k = 0; k < 4; ++k) {
          const int x = x0 + (k & 1), y = y0 + (k >> 1);
          if (bw[k] <= 0.0 || x < 0 || y < 0 || x >= int(W) || y >= int(H)) continue;
          const uint j = uint(y) * W + uint(x);
          if (has(F_VALID) && !(sValid[pc.validPlane * plane + j] > 0.0)) continue;
          const vec3 q = vec3(sNormal[j], sNormal[plane + j], sNormal[2u * plane + j]);
          precise float d = n.x * q.x + n.y * q.y + n.z * q.z;
          if (!(d >= pc.normalTolerance)) continue;
          if (has(F_ID) && sId[j] != id) continue;
          if (has(F_DEPTH)) {
            const float slope = has(F_GRADIENT) ? max(abs(sGrad[j]), abs(sGrad[plane + j])) : 0.0;
            precise float tol = pc.depthTolerance * z + pc.depthGradientScale * slope;
            if (!(abs(sDepth[j] - z) <= tol)) continue;
          }
          index[count] = j;
          weight[count] = bw[k];
          ++count;
          sum += bw[k];
        }
      }
    }
  }
  if (!(sum > 1e-4)) count = 0u;
  for (uint ch = 0; ch < 3; ++ch) {
    if (count == 0u) {
      outp[ch * plane + i] = a[ch];
      continue;
    }
    precise float b = 0.0;
    for (uint k = 0; k < count; ++k) b += (weight[k] / sum) * sLight[ch * plane + index[k]];
    precise float o = (1.0 - pc.blend) * a[ch] + pc.blend * b;
    outp[ch * plane + i] = o;
  }
}
