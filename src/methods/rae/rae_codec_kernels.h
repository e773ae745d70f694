// The RAE's colour transform on whole rows (rae_codec_simd.cpp, one copy per CPU path,
// core/simd.h), called by rae_model.cpp's encode and decode through RTD_SIMD.
#pragma once
#include "core/simd_dispatch.h"

RTD_SIMD_DECLARE(
/// out[i] = log1p(max(c[i], 0) / k[i]) for i < n (k null: k = 1); c, out may not overlap.
/// Within 2 ulp of log1p (of the value the division rounds to).
void raeLog1pRatio(const float* c, const float* k, float* out, int n);
/// out[i] = expm1(clamp(y[i], 0, yMax)) * k[i] for i < n (k null: k = 1), yMax <= 80.
/// Within 2 ulp of expm1 (times k).
void raeExpm1Scaled(const float* y, const float* k, float* out, int n, float yMax);
)
