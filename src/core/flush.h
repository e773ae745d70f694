// No subnormal floats in the hot loops (issue 20). Intel cores compute with subnormal operands
// and results through microcode assists, tens to hundreds of times slower than normal
// arithmetic (an SVGF frame took 2.6x longer on a Sapphire Rapids Xeon with the caller's
// default floating-point mode than with flush-to-zero set). The library never changes the
// caller's MXCSR; instead its arithmetic is arranged so that subnormals do not arise:
//
// - every value a pass stores (planes, history, outputs) is 0 or at least kTiny in magnitude
//   (import flushes smaller inputs to 0, passes flush what they store);
// - an edge-stopping weight below 2^kMinWeightExp2 is exactly 0 (the polynomial exp clamps its
//   exponent; the a-trous filter cuts a tap's weight with its kernel coefficient, h w, as a
//   whole), so a weight times a kernel coefficient is 0 or >= 2^-32 (>= 2^-24 in the a-trous
//   filter), its square >= 2^-64, and their products with stored values stay normal (>= 2^-124);
// - a square of a stored value is taken as squareOrZero (0 below sqrt(kTiny)), so moments and
//   variances also obey the first rule.
//
// Dropping values this small changes no result measurably: kTiny is 8.7e-19 (radiance that
// small is black in any image), and a dropped weight is below float rounding of the weighted
// sum it would have entered (< 2^-24 of the centre tap's weight).
#pragma once
#include <cmath>

namespace rtd {

/// Magnitudes below this are stored as 0.
constexpr float kTiny = 0x1p-60f;
/// sqrt(kTiny): squares of smaller magnitudes are taken as 0.
constexpr float kTinyRoot = 0x1p-30f;
/// exp(-x) weights below 2^kMinWeightExp2 are 0: x > -kMinWeightExp2 ln 2.
constexpr int kMinWeightExp2 = -24;
constexpr float kMaxWeightExponent = 24.0f * 0.693147180559945f;

/// Depth-weight denominators sigma_z |grad z . (p - q)| are clamped here: a depth difference
/// over a larger one is 0 to float precision anyway, and the quotient of a tiny difference by
/// a huge denominator would underflow.
constexpr float kMaxDepthDenominator = 0x1p40f;

inline float flushTiny(float v) { return std::abs(v) < kTiny ? 0.0f : v; }
inline float squareOrZero(float v) { return std::abs(v) < kTinyRoot ? 0.0f : v * v; }
/// exp(-x) for x >= 0, exactly 0 where it would be below 2^kMinWeightExp2 (the scalar twin of
/// the vectorized weights' exp).
inline float weightExp(float x) { return x < kMaxWeightExponent ? std::exp(-x) : 0.0f; }


}  // namespace rtd
