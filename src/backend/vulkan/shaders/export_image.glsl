// Body of the "export_image_*" passes: three planes, plus the separated emission when the frame
// has one, into the application's storage image (alpha = 1). The including shader defines
// IMAGE_FORMAT (rgba32f or rgba16f: a storage image's format must be declared unless the device
// has shaderStorageImageWriteWithoutFormat, which Vulkan does not guarantee).
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Src { float src[]; };
layout(binding = 1, IMAGE_FORMAT) uniform writeonly image2D dst;
layout(std430, binding = 2) readonly buffer Emission { float emission[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint addEmission;  // binding 2 holds the emission planes
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  vec4 v = vec4(0.0, 0.0, 0.0, 1.0);
  for (uint c = 0; c < 3; ++c) v[c] = pc.addEmission != 0 ? src[c * plane + i] + emission[c * plane + i] : src[c * plane + i];
  imageStore(dst, ivec2(p), v);
}
