// halvesToFloats / floatsToHalves' loops (half_simd.cpp), one copy per CPU path (core/simd.h),
// called by half.cpp through RTD_SIMD.
#pragma once
#include <cstddef>

#include "core/simd_dispatch.h"

RTD_SIMD_DECLARE(
void halvesToFloatsBulk(const char* src, float* dst, size_t n);
void floatsToHalvesBulk(const float* src, char* dst, size_t n);
)
