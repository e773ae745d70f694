#include "core/cpu_path.h"

#include <atomic>
#include <cstdlib>
#include <optional>
#include <string_view>

#include "rtd/error.h"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

namespace rtd {

namespace {

#if defined(__x86_64__) || defined(__i386__)
// F16C from CPUID leaf 1 (ECX bit 29): clang 14's __builtin_cpu_supports does not know "f16c".
bool hasF16c() {
  unsigned a, b, c, d;
  return __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C);
}
#endif

constexpr const char* kNames[kCpuPathCount] = {"sse2", "avx2", "avx512"};

std::optional<CpuPath> parse(std::string_view s) {
  for (int i = 0; i < kCpuPathCount; ++i)
    if (s == kNames[i]) return CpuPath(i);
  return std::nullopt;
}

// The environment's choice: nullopt for unset or "auto".
std::optional<CpuPath> requested(bool& invalid) {
  invalid = false;
  const char* env = std::getenv("RTD_CPU_PATH");
  if (!env || !*env || std::string_view(env) == "auto") return std::nullopt;
  const auto p = parse(env);
  if (!p || !cpuPathSupported(*p)) {
    invalid = true;
    return std::nullopt;
  }
  return p;
}

std::atomic<int> active{-1};

}  // namespace

const char* cpuPathName(CpuPath p) { return kNames[int(p)]; }

bool cpuPathSupported(CpuPath p) {
#if defined(__x86_64__) || defined(__i386__)
  // libgcc's feature bits include the OS check (XGETBV) for the AVX and AVX-512 register state.
  switch (p) {
    case CpuPath::Sse2: return true;
    case CpuPath::Avx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && hasF16c() &&
             __builtin_cpu_supports("bmi2");
    case CpuPath::Avx512:
      return cpuPathSupported(CpuPath::Avx2) && __builtin_cpu_supports("avx512f") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512cd");
  }
  return false;
#else
  return p == CpuPath::Sse2;
#endif
}

CpuPath bestCpuPath() {
  for (int i = kCpuPathCount - 1; i > 0; --i)
    if (cpuPathSupported(CpuPath(i))) return CpuPath(i);
  return CpuPath::Sse2;
}

CpuPath cpuPath() {
  int p = active.load(std::memory_order_relaxed);
  if (p < 0) {
    bool invalid;
    const auto r = requested(invalid);
    int expected = -1;
    active.compare_exchange_strong(expected, int(r ? *r : bestCpuPath()));
    p = active.load(std::memory_order_relaxed);
  }
  return CpuPath(p);
}

void checkCpuPathSetting() {
  bool invalid;
  requested(invalid);
  if (!invalid) return;
  const std::string value = std::getenv("RTD_CPU_PATH");
  std::string runs;
  for (int i = 0; i < kCpuPathCount; ++i)
    if (cpuPathSupported(CpuPath(i))) runs += std::string(runs.empty() ? "" : ", ") + kNames[i];
  if (!parse(value)) throw Error("RTD_CPU_PATH='" + value + "' is not a CPU path (auto, sse2, avx2, avx512)");
  throw Error("RTD_CPU_PATH='" + value + "': this CPU does not run it (it runs " + runs + ")");
}

CpuPath setCpuPath(CpuPath p) {
  if (!cpuPathSupported(p)) throw Error(std::string("this CPU does not run the ") + kNames[int(p)] + " path");
  const CpuPath old = cpuPath();
  active.store(int(p), std::memory_order_relaxed);
  return old;
}

std::string describeCpuPath() {
  std::string s = std::string(cpuPathName(cpuPath())) + " (this CPU runs ";
  for (int i = 0, n = 0; i < kCpuPathCount; ++i)
    if (cpuPathSupported(CpuPath(i))) s += std::string(n++ ? ", " : "") + kNames[i];
  return s + (std::getenv("RTD_CPU_PATH") ? "; RTD_CPU_PATH set)" : ")");
}

}  // namespace rtd
