// The dispatching half of runtime dispatch (src/core/cpu_path.h, src/core/simd.h): declare a
// *_simd.cpp file's entry points once for every path, call the current path's copy.
//
//   // atrous_kernels.h
//   RTD_SIMD_DECLARE(void atrousRows(const AtrousGuide&, ...);)
//   // atrous.cpp
//   RTD_SIMD(atrousRows)(guide, ...);
#pragma once
#include "core/cpu_path.h"

#define RTD_SIMD_DECLARE(...)   \
  namespace rtd::sse2 {         \
  __VA_ARGS__                   \
  }                             \
  namespace rtd::avx2 {         \
  __VA_ARGS__                   \
  }                             \
  namespace rtd::avx512 {       \
  __VA_ARGS__                   \
  }

/// The current path's copy of entry point `name`.
#define RTD_SIMD(name) (::rtd::simd::pick(&::rtd::sse2::name, &::rtd::avx2::name, &::rtd::avx512::name))

namespace rtd::simd {
template <class F> F pick(F sse2, F avx2, F avx512) {
  switch (cpuPath()) {
    case CpuPath::Avx512: return avx512;
    case CpuPath::Avx2: return avx2;
    default: return sse2;
  }
}
}  // namespace rtd::simd
