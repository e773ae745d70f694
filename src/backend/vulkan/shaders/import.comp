#version 450
// Pass "import": one buffer of the frame, as the application laid it out (any pixel and row
// stride, float, int32 or half), into planes; radiance made finite and non-negative, features
// finite (NaN never reaches history). Counts replaced values.
#include "common.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(std430, binding = 2) buffer Counter { uint replaced[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint srcOffset, pixelStride, rowStride;  // in 32-bit words; for halves in 16-bit units
  uint channels;
  uint type;      // 0: float, 1: int32 (ids), 2: half (IEEE binary16, two per word, low half first)
  uint radiance;  // clamp negatives too
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint s = pc.srcOffset + p.y * pc.rowStride + p.x * pc.pixelStride;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  uint bad = 0;
  for (uint c = 0; c < pc.channels; ++c) {
    float v;
    if (pc.type == 2u) {
      const uint e = s + c;
      const vec2 pair = unpackHalf2x16(src[e >> 1]);
      v = (e & 1u) != 0u ? pair.y : pair.x;
    } else {
      const uint bits = src[s + c];
      v = pc.type == 1u ? float(int(bits)) : uintBitsToFloat(bits);
    }
    // Ordered comparisons are false for NaN; the bound rejects +Inf (and -Inf via the abs).
    const bool ok = pc.radiance != 0 ? (v >= 0.0 && v <= 3.0e38) : (abs(v) <= 3.0e38);
    if (!ok) { v = 0.0; ++bad; }
    dst[c * plane + i] = v;
  }
  if (bad != 0) atomicAdd(replaced[0], bad);
}
