#version 450
// Pass "reflections" (per-pixel features of SVGF's Voorhuis mode; svgf::Reflections::prepare
// in src/methods/svgf/svgf_reflections.cpp): from the surface classes (0 diffuse, 1 glossy,
// 2 glossy with reflection motion, 3 mirror)
//   - the blend floor: alphaSpecular on specular, alphaColor on diffuse pixels (Sec. 7);
//   - Eq. 6's falloff c = 1/(2 sigma^2) - 1/2, sigma = exp(-footprint / omega), on class 2;
//     with F_LOBE omega is in widths of the reflected lobe, 2 roughness^2 |reflPos - position|
//     (svgf::reflectedLobeWidth), and 0 where the mirror ray escapes (zero reflected normal);
//   - the guide of the reflected geometry (Sec. 4.1): mirror pixels get the reflected normal
//     and the view depth of the virtual image (primary depth x path length / primary distance;
//     kMissDepth where the mirror shows the sky); other pixels their own features; and the
//     key that keeps mirror pixels apart from the others in the a-trous levels (1 / 0).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Cls { float cls[]; };
layout(std430, binding = 1) readonly buffer Normal { float normal[]; };
layout(std430, binding = 2) readonly buffer Depth { float depth[]; };
layout(std430, binding = 3) readonly buffer Position { float position[]; };
layout(std430, binding = 4) readonly buffer ReflPos { float reflPos[]; };
layout(std430, binding = 5) readonly buffer ReflNormal { float reflNormal[]; };
layout(std430, binding = 6) readonly buffer Footprint { float footprint[]; };
layout(std430, binding = 7) writeonly buffer Alpha { float alphaOut[]; };
layout(std430, binding = 8) writeonly buffer Falloff { float falloffOut[]; };
layout(std430, binding = 9) writeonly buffer GuideDepth { float guideDepth[]; };
layout(std430, binding = 10) writeonly buffer GuideNormal { float guideNormal[]; };
layout(std430, binding = 11) readonly buffer Rough { float roughness[]; };
layout(std430, binding = 12) writeonly buffer MirrorKey { float mirrorKey[]; };

#define F_ALPHA 1u
#define F_FALLOFF 2u
#define F_GUIDE 4u
#define F_EYE 8u
#define F_LOBE 16u

layout(push_constant) uniform PC {
  uint width, height, flags;
  float alphaColor, alphaSpecular, omega;
  float eyeX, eyeY, eyeZ;
} pc;

const float kMissDepth = 1e4;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  const float c = cls[i];
  if ((pc.flags & F_ALPHA) != 0u) alphaOut[i] = c != 0.0 ? pc.alphaSpecular : pc.alphaColor;
  if ((pc.flags & F_FALLOFF) != 0u) {
    float f = 0.0;
    bool sky = false;
    float omega = pc.omega;
    if (c == 2.0 && (pc.flags & F_LOBE) != 0u) {
      precise float n2 = 0.0, t2 = 0.0;
      for (uint k = 0; k < 3u; ++k) {
        const float nk = reflNormal[k * n + i];
        precise float d = reflPos[k * n + i] - position[k * n + i];
        n2 += nk * nk;
        t2 += d * d;
      }
      sky = n2 < 0.25;
      const float r = clamp(roughness[i], 0.0, 1.0);
      precise float width = max(2.0 * r * r * max(0.0, sqrt(t2)), 1e-30);
      omega *= width;
    }
    if (c == 2.0 && !sky) {
      const float s = clamp(exp(-max(0.0, footprint[i]) / omega), 1e-3, 1.0);
      f = 0.5 / (s * s) - 0.5;  // glossySpatialFalloff(glossySpatialSigma(...))
    }
    falloffOut[i] = f;
  }
  if ((pc.flags & F_GUIDE) == 0u) return;
  mirrorKey[i] = c == 3.0 ? 1.0 : 0.0;  // the a-trous levels keep mirror pixels apart
  float z = depth[i];
  vec3 nn = vec3(normal[i], normal[n + i], normal[2u * n + i]);
  if (c == 3.0) {
    nn = vec3(reflNormal[i], reflNormal[n + i], reflNormal[2u * n + i]);
    const vec3 pp = vec3(position[i], position[n + i], position[2u * n + i]);
    const vec3 r = vec3(reflPos[i], reflPos[n + i], reflPos[2u * n + i]);
    const vec3 eye = vec3(pc.eyeX, pc.eyeY, pc.eyeZ);
    precise float t2 = 0.0, t1 = 0.0;
    for (int k = 0; k < 3; ++k) {
      t2 += (r[k] - pp[k]) * (r[k] - pp[k]);
      if ((pc.flags & F_EYE) != 0u) t1 += (pp[k] - eye[k]) * (pp[k] - eye[k]);
    }
    precise float nl = nn.x * nn.x + nn.y * nn.y + nn.z * nn.z;
    const bool sky = nl < 0.25;
    t1 = (pc.flags & F_EYE) != 0u ? sqrt(t1) : z;
    precise float zv = t1 > 0.0 ? z * (t1 + sqrt(t2)) / t1 : z;
    z = sky ? kMissDepth : zv;
  }
  guideDepth[i] = z;
  for (uint k = 0; k < 3u; ++k) guideNormal[k * n + i] = nn[k];
}
