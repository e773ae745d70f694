#version 450
// Pass "import": one buffer of the frame, as the application laid it out (any pixel and row
// stride, float, int32 or half), into planes, every value made finite and clamped into the
// buffer's range (sanitize.glsl; NaN never reaches history). Counts replaced values per buffer.
#include "common.glsl"
#include "sanitize.glsl"
RTD_LOCAL_SIZE

layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(std430, binding = 2) buffer Counter { uint replaced[]; };

layout(push_constant) uniform PC {
  uint width, height;
  uint srcOffset, pixelStride, rowStride;  // in 32-bit words; for halves in 16-bit units
  uint channels;
  uint type;      // 0: float, 1: int32 (ids), 2: half (IEEE binary16, two per word, low half first)
  uint counter;   // 3 * the buffer's index (sanitize.glsl)
  float lo, hi;   // the buffer's range (importRange)
} pc;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (outside(p, pc.width, pc.height)) return;
  const uint s = pc.srcOffset + p.y * pc.rowStride + p.x * pc.pixelStride;
  const uint i = p.y * pc.width + p.x, plane = pc.width * pc.height;
  uint nonFinite = 0, outOfRange = 0;
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
    dst[c * plane + i] = sanitizeValue(v, pc.lo, pc.hi, nonFinite, outOfRange);
  }
  if (nonFinite != 0) atomicAdd(replaced[pc.counter + kCountNonFinite], nonFinite);
  if (outOfRange != 0) atomicAdd(replaced[pc.counter + kCountOutOfRange], outOfRange);
}
