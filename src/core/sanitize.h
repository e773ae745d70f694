// Input sanitization, the same on both backends: the range every buffer's values are clamped
// into on import (frame_data.cpp's import loops and the Vulkan import shaders apply it) and the
// renormalization of unit vectors that import applies (renormalizeRow; its GLSL twin is
// src/backend/vulkan/shaders/sanitize_unit_vectors.comp). docs/input-validation.md has the table.
#pragma once
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cfloat>
#include <cmath>

#include "core/flush.h"
#include "rtd/denoiser.h"
#include "rtd/frame.h"

namespace rtd {

/// Per-buffer counts of what import replaced.
using SanitizeStats = std::array<SanitizeCounts, kBufferCount>;

/// Import makes every value v of a buffer finite and puts it in [lo, hi]: NaN and +-Inf
/// become 0 (FrameStats counts them as nonFinite), finite values outside are clamped (outOfRange).
struct ValueRange {
  float lo, hi;
};

/// Motion vectors are clamped to +-2^24 pixels (far off any image; float pixel positions stop
/// being exact there); ids and seeds to +-2^24 (integers are exact in float below it).
constexpr float kMaxMotion = 16777216.0f;
constexpr float kMaxId = 16777216.0f;

/// The range of buffer b's values after import.
ValueRange importRange(Buffer b);

/// v made finite and put into r, counted in `bad`: the scalar rule of every import path (float
/// and half rows; sanitize.glsl is its GLSL twin). Non-finite values become 0 (counted),
/// magnitudes below kTiny 0 (not counted: the hot loops never see a subnormal, core/flush.h),
/// values outside r are clamped (counted). Decided on the bits, so a subnormal input is never
/// the operand of a floating-point instruction.
inline float sanitizeValue(float v, ValueRange r, SanitizeCounts& bad) {
  const uint32_t magnitude = std::bit_cast<uint32_t>(v) & 0x7fffffffu;
  if (magnitude > std::bit_cast<uint32_t>(FLT_MAX)) {  // NaN and infinities
    ++bad.nonFinite;
    return 0.0f;
  }
  if (magnitude < std::bit_cast<uint32_t>(kTiny)) v = 0.0f;
  if (v < r.lo || v > r.hi) {
    ++bad.outOfRange;
    return v < r.lo ? r.lo : r.hi;
  }
  return v;
}

/// Buffers holding unit vectors (normal, reflectedNormal, mirrorDirection): renormalized after import.
bool isUnitVectorBuffer(Buffer b);

/// A vector whose squared length is farther than this from 1 is renormalized: looser than the
/// rounding of any unit vector written in float, so valid inputs pass bit for bit.
constexpr float kUnitLengthTolerance = 1e-3f;

/// Renormalizes (x, y, z) in place unless it is of unit length (within kUnitLengthTolerance)
/// or (0, 0, 0), which means "no surface" and is kept: normal weights and reprojection tests
/// then reject the pixel's neighbours and history. A vector too short to have a direction
/// (every component below FLT_MIN) becomes (0, 0, 0). Returns whether the vector changed.
/// Scaled by its largest component first, so neither squares overflow nor tiny ones underflow.
inline bool renormalize(float& x, float& y, float& z) {
  const float l2 = x * x + y * y + z * z;
  if (std::abs(l2 - 1.0f) <= kUnitLengthTolerance) return false;
  const float m = std::max({std::abs(x), std::abs(y), std::abs(z)});
  if (m == 0.0f) return false;
  if (m < FLT_MIN) {
    x = y = z = 0.0f;
    return true;
  }
  x /= m;
  y /= m;
  z /= m;
  const float inv = 1.0f / std::sqrt(x * x + y * y + z * z);
  x *= inv;
  y *= inv;
  z *= inv;
  return true;
}

/// Renormalizes the pixels of one row of a unit-vector buffer (its x, y, z rows) in place;
/// returns how many changed. importFrame() calls it on every row of such a buffer that may
/// need it. Valid rows (the common case) only pay for a vectorizable test.
uint64_t renormalizeRow(float* px, float* py, float* pz, int w);

}  // namespace rtd
