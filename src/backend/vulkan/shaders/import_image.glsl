// Body of the "import_image_*" passes: one buffer of the frame from the application's VkImage
// (a sampled image read with texelFetch: any sampleable format, no sampler needed) into planes,
// with the sanitization of import.comp. The including shader defines IMAGE_TYPE (texture2D,
// itexture2D or utexture2D) before including this file.
#extension GL_EXT_samplerless_texture_functions : require
#include "common.glsl"
#include "sanitize.glsl"
RTD_LOCAL_SIZE

layout(binding = 0) uniform IMAGE_TYPE src;
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(std430, binding = 2) buffer Counter { uint replaced[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint channels;
  uint counter;   // 3 * the buffer's index (sanitize.glsl)
  float lo, hi;   // the buffer's range (importRange)
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  const vec4 texel = vec4(texelFetch(src, ivec2(p), 0));
  uint nonFinite = 0, outOfRange = 0;
  for (uint c = 0; c < pc.channels; ++c) dst[c * plane + i] = sanitizeValue(texel[c], pc.lo, pc.hi, nonFinite, outOfRange);
  if (nonFinite != 0) atomicAdd(replaced[pc.counter + kCountNonFinite], nonFinite);
  if (outOfRange != 0) atomicAdd(replaced[pc.counter + kCountOutOfRange], outOfRange);
}
