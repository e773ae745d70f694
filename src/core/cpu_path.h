// Runtime choice of the CPU code path (issue 20). The library is built for any x86-64: the hot
// loops (src/**/*_simd.cpp) are compiled once per path, each copy in its own namespace
// (rtd::sse2, rtd::avx2, rtd::avx512; src/core/simd.h), and every pass calls the copy of the
// path chosen here (RTD_SIMD below): the best one this CPU runs, or the one the environment
// variable RTD_CPU_PATH names (sse2, avx2, avx512, or auto). docs/performance.md lists which
// passes use which vector width on each path.
#pragma once
#include <cstdint>
#include <string>

namespace rtd {

enum class CpuPath : uint8_t {
  Sse2,    ///< any x86-64 (SSE2, 4 lanes); on other architectures the portable build
  Avx2,    ///< AVX2 + FMA + F16C (x86-64-v3), 8 lanes
  Avx512,  ///< AVX-512 F/VL/BW/DQ/CD (x86-64-v4), 16 lanes where it pays
};
constexpr int kCpuPathCount = 3;

const char* cpuPathName(CpuPath p);
/// Whether this CPU (and the operating system's saved register state) runs path p.
bool cpuPathSupported(CpuPath p);
/// The widest path this CPU runs.
CpuPath bestCpuPath();
/// The path the passes take: RTD_CPU_PATH when set (and not "auto"), else bestCpuPath(). Read
/// once; an unknown or unsupported name falls back to bestCpuPath() here, and makes
/// Device::create throw (checkCpuPathSetting).
CpuPath cpuPath();
/// Throws rtd::Error if RTD_CPU_PATH names an unknown path or one this CPU lacks.
void checkCpuPathSetting();
/// Forces a path for the whole process (tests; not thread-safe with running passes); returns
/// the previous one. Throws rtd::Error if this CPU lacks it.
CpuPath setCpuPath(CpuPath p);
/// "avx512 (this CPU runs sse2, avx2, avx512)" and similar, for `rtdenoise devices`/`bench`.
std::string describeCpuPath();

}  // namespace rtd
