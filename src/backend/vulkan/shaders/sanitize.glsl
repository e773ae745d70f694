// Input sanitization, twin of src/core/sanitize.h and of the import loops of
// src/core/frame_data.cpp: the counters (binding `Counter` of the including shader, three per
// buffer: non-finite, out of range, renormalized) and the per-value and per-vector rules.

// Values of buffer b replaced on import are counted at replaced[3 * b + kind].
const uint kCountNonFinite = 0u, kCountOutOfRange = 1u, kCountRenormalized = 2u;

// Non-finite -> 0, finite values clamped into [lo, hi] (Bounds::sanitize). Ordered comparisons
// are false for NaN; the abs bound rejects +-Inf.
float sanitizeValue(float v, float lo, float hi, inout uint nonFinite, inout uint outOfRange) {
  if (!(abs(v) <= 3.40282347e38)) {
    ++nonFinite;
    return 0.0;
  }
  if (v < lo || v > hi) {
    ++outOfRange;
    return v < lo ? lo : hi;
  }
  return v;
}

// renormalize() of src/core/sanitize.h: unit vectors within the tolerance and (0, 0, 0) are
// kept, vectors with every component below FLT_MIN become 0, others are scaled by their largest
// component and normalized. Returns whether the vector changed.
const float kUnitLengthTolerance = 1e-3;
bool renormalize(inout vec3 n) {
  precise float l2 = n.x * n.x + n.y * n.y + n.z * n.z;
  if (abs(l2 - 1.0) <= kUnitLengthTolerance) return false;
  const float m = max(abs(n.x), max(abs(n.y), abs(n.z)));
  if (m == 0.0) return false;
  if (m < 1.17549435e-38) {
    n = vec3(0.0);
    return true;
  }
  n /= m;
  precise float s = n.x * n.x + n.y * n.y + n.z * n.z;
  n *= 1.0 / sqrt(s);
  return true;
}
