// Both backends for tests that must hold on each: the CPU device, and the Vulkan device of the
// test run (lavapipe in CI; vulkan/vulkan_test_util.h), whose absence fails the test unless
// RTD_SKIP_VULKAN_TESTS=1 is set.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "rtd/rtd.h"
#include "vulkan/vulkan_test_util.h"

namespace rtd::test {

inline std::vector<Backend> testBackends() { return {Backend::Cpu, Backend::Vulkan}; }

/// Every registered method that runs on `backend`.
inline std::vector<std::string> methodsOn(Backend backend) {
  std::vector<std::string> out;
  for (const MethodInfo& m : listMethods())
    if (backend == Backend::Cpu ? m.cpu : m.vulkan) out.push_back(m.name);
  return out;
}

/// The shared device of a backend; null when there is no Vulkan device (after ADD_FAILURE,
/// unless RTD_SKIP_VULKAN_TESTS=1).
inline Device* testDevice(Backend backend) {
  static std::unique_ptr<Device> cpu = Device::create({.backend = Backend::Cpu, .threads = 2});
  if (backend == Backend::Cpu) return cpu.get();
  std::string why;
  Device* vulkan = vulkanDevice(&why);
  if (!vulkan) {
    const char* skip = std::getenv("RTD_SKIP_VULKAN_TESTS");
    if (!(skip && std::string(skip) == "1")) ADD_FAILURE() << "no Vulkan device (set RTD_SKIP_VULKAN_TESTS=1 to skip): " << why;
  }
  return vulkan;
}

}  // namespace rtd::test
