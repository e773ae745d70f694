// Reads a vk::Planes back to the host, for the tests of single Vulkan passes.
#pragma once
#include <vector>

#include "backend/vulkan/context.h"

namespace rtd::test {

inline std::vector<float> download(vk::Context& ctx, const vk::Planes& p) {
  std::vector<float> v(p.planeSize() * size_t(p.count));
  ctx.download(p.buffer, v.data(), v.size() * 4);
  return v;
}

}  // namespace rtd::test
