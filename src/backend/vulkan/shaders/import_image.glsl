// Body of the "import_image_*" passes: one buffer of the frame from the application's VkImage
// (a sampled image read with texelFetch: any sampleable format, no sampler needed) into planes,
// with the sanitization of import.comp. The including shader defines IMAGE_TYPE (texture2D,
// itexture2D or utexture2D) before including this file.
#extension GL_EXT_samplerless_texture_functions : require
#include "common.glsl"
RTD_LOCAL_SIZE

layout(binding = 0) uniform IMAGE_TYPE src;
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(std430, binding = 2) buffer Counter { uint replaced[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint channels;
  uint radiance;  // clamp negatives too
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  const vec4 texel = vec4(texelFetch(src, ivec2(p), 0));
  uint bad = 0;
  for (uint c = 0; c < pc.channels; ++c) {
    float v = texel[c];
    // Ordered comparisons are false for NaN; the bound rejects +Inf (and -Inf via the abs).
    const bool ok = pc.radiance != 0 ? (v >= 0.0 && v <= 3.0e38) : (abs(v) <= 3.0e38);
    if (!ok) { v = 0.0; ++bad; }
    dst[c * plane + i] = v;
  }
  if (bad != 0) atomicAdd(replaced[0], bad);
}
