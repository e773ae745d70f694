// Method "bmfr" on the CPU: the pipeline (bmfr_simd.cpp) is compiled once per CPU path
// (core/simd.h); a denoiser runs the path that is current when it is created.
#include <memory>

#include <tbb/task_arena.h>

#include "core/simd_dispatch.h"
#include "rtd/denoiser.h"

RTD_SIMD_DECLARE(std::unique_ptr<Denoiser> createBmfrCpu(tbb::task_arena& arena);)

namespace rtd {
std::unique_ptr<Denoiser> createBmfrCpu(tbb::task_arena& arena) { return RTD_SIMD(createBmfrCpu)(arena); }
}  // namespace rtd
