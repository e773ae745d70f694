// Forcing each CPU code path in turn (src/core/cpu_path.h) in tests.
#pragma once
#include <vector>

#include "core/cpu_path.h"

namespace rtd::test {

/// Every path this machine runs, narrowest first.
inline std::vector<CpuPath> supportedCpuPaths() {
  std::vector<CpuPath> v;
  for (int i = 0; i < kCpuPathCount; ++i)
    if (cpuPathSupported(CpuPath(i))) v.push_back(CpuPath(i));
  return v;
}

/// Makes `path` current until the end of the scope.
class ScopedCpuPath {
 public:
  explicit ScopedCpuPath(CpuPath path) : previous_(setCpuPath(path)) {}
  ~ScopedCpuPath() { setCpuPath(previous_); }
  ScopedCpuPath(const ScopedCpuPath&) = delete;
  ScopedCpuPath& operator=(const ScopedCpuPath&) = delete;

 private:
  CpuPath previous_;
};

}  // namespace rtd::test
