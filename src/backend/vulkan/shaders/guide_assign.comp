#version 450
// Pass "guideRays.premix", first half: which guide ray each non-guide sample joins (Voorhuis
// 2018 Sec. 5; GuideRays::premix in src/passes/guide_rays.cpp). Sample k of pixel (x, y) lies at
// (x + 0.5 + ox, y + 0.5 + oy), in the cell of the four pixel centres around it; it joins the
// guide of smallest |z_s - z_g| / max(z_s, z_g) + normalWeight (1 - n_s . n_g), guides outside
// the image excluded (Fig. 7), ties to its own pixel, then in scan order.
// Unlike the other passes these buffers are interleaved (the host frames' layout): the
// pre-mixed frame goes to the denoiser as VulkanBufferViews, which are interleaved.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer GuideDepth { float guideDepth[]; };
layout(std430, binding = 1) readonly buffer GuideNormal { float guideNormal[]; };    // 3 per pixel
layout(std430, binding = 2) readonly buffer SampleDepth { float sampleDepth[]; };    // sample k at k * w * h
layout(std430, binding = 3) readonly buffer SampleNormal { float sampleNormal[]; };  // 3 per pixel
layout(std430, binding = 4) readonly buffer Offsets { float offsets[]; };            // 2 per pixel
layout(std430, binding = 5) writeonly buffer Assigned { uint assigned[]; };          // index of the guide

layout(push_constant) uniform PC { uint width, height, samples; float normalWeight; } pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, n = pc.width * pc.height;
  for (uint k = 0; k < pc.samples; ++k) {
    const uint s = k * n + i;
    const float px = float(p.x) + offsets[2 * s], py = float(p.y) + offsets[2 * s + 1];
    const int x0 = int(floor(px)), y0 = int(floor(py));
    const float z = sampleDepth[s];
    const vec3 ns = vec3(sampleNormal[3 * s], sampleNormal[3 * s + 1], sampleNormal[3 * s + 2]);
    float best = uintBitsToFloat(0x7f800000u);  // +inf
    uint bestIndex = i;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int qx = x0 + dx, qy = y0 + dy;
        if (qx < 0 || qy < 0 || qx >= int(pc.width) || qy >= int(pc.height)) continue;
        const uint q = uint(qy) * pc.width + uint(qx);
        const float zg = guideDepth[q];
        const vec3 ng = vec3(guideNormal[3 * q], guideNormal[3 * q + 1], guideNormal[3 * q + 2]);
        const float scale = max(max(z, zg), 1e-12);
        // Without fused multiply-add, as the CPU, so both take the same decisions.
        precise float cosine = ns.x * ng.x + ns.y * ng.y + ns.z * ng.z;
        precise float d = abs(z - zg) / scale + pc.normalWeight * (1.0 - cosine);
        if (d < best || (d == best && q == i)) {
          best = d;
          bestIndex = q;
        }
      }
    assigned[s] = bestIndex;
  }
}
