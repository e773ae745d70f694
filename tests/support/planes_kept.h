// What a CPU denoiser keeps, from PlaneInspection (src/backend/cpu/cpu_denoiser.h), in tests.
#pragma once
#include <cstddef>
#include <string_view>

#include "backend/cpu/cpu_denoiser.h"
#include "rtd/denoiser.h"

namespace rtd::test {

/// Floats held in the planes of a CPU denoiser that the visitors name `plane`.
inline size_t floatsKept(const Denoiser& d, std::string_view plane) {
  size_t n = 0;
  dynamic_cast<const PlaneInspection&>(d).forEachPlane([&](std::string_view name, const float*, size_t count) {
    if (name == plane) n += count;
  });
  return n;
}

}  // namespace rtd::test
