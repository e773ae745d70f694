// qr.h's functions: the current CPU path's copy (qr_simd.cpp, core/simd.h).
#include "methods/bmfr/qr.h"

#include "core/simd_dispatch.h"

RTD_SIMD_DECLARE(namespace bmfr {
using rtd::bmfr::kMaxChannels;
using rtd::bmfr::kMaxFeatures;
using rtd::bmfr::TriangularSystem;
void householderQr(float* cols, int rows, size_t stride, int features, int channels, TriangularSystem& out);
void householderQrTiled(float* tiles, int rows, int tileRows, size_t tileStride, int features, int channels,
                        TriangularSystem& out);
int backSubstitute(const TriangularSystem& s, float alpha[kMaxChannels][kMaxFeatures], float relativePivotTolerance);
})

namespace rtd::bmfr {

void householderQr(float* cols, int rows, size_t stride, int features, int channels, TriangularSystem& out) {
  RTD_SIMD(bmfr::householderQr)(cols, rows, stride, features, channels, out);
}

void householderQrTiled(float* tiles, int rows, int tileRows, size_t tileStride, int features, int channels,
                        TriangularSystem& out) {
  RTD_SIMD(bmfr::householderQrTiled)(tiles, rows, tileRows, tileStride, features, channels, out);
}

int backSubstitute(const TriangularSystem& s, float alpha[kMaxChannels][kMaxFeatures], float relativePivotTolerance) {
  return RTD_SIMD(bmfr::backSubstitute)(s, alpha, relativePivotTolerance);
}

}  // namespace rtd::bmfr
