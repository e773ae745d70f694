// Device::create and the CPU device: a oneTBB arena that every CPU denoiser runs in.
#include <tbb/info.h>
#include <map>
#include <memory>
#include <mutex>
#include <tbb/task_arena.h>

#include "core/api_guard.h"
#include "core/cpu_path.h"
#include "core/registry.h"
#include "core/stereo_pair.h"
#include "rtd/denoiser.h"

namespace rtd {

namespace {

// Denoisers hold a reference to their device's arena and may outlive the Device object
// (`Device::create()->createDenoiser(...)` is a natural thing to write), so arenas live for
// the whole process: one per thread count, created on first use.
tbb::task_arena& arenaFor(int threads) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  std::lock_guard lock(mutex);
  auto& a = arenas[threads];
  if (!a) a = std::make_unique<tbb::task_arena>(threads);
  return *a;
}

class CpuDevice final : public Device {
 public:
  explicit CpuDevice(int threads)
      : threads_(threads > 0 ? threads : tbb::info::default_concurrency()), arena_(arenaFor(threads_)) {}
  Backend backend() const override { return Backend::Cpu; }
  std::string name() const override {
    return "CPU (" + std::to_string(threads_) + " threads, oneTBB, " + cpuPathName(cpuPath()) + ")";
  }
  std::unique_ptr<Denoiser> createDenoiser(std::string_view method) override {
    const MethodEntry* e = findMethod(method);
    if (!e) throw Error("unknown method '" + std::string(method) + "' (see `rtdenoise methods`)");
    if (!e->createCpu) throw Error("method '" + std::string(method) + "' has no CPU implementation");
    return e->createCpu(arena_);
  }
  std::unique_ptr<StereoDenoiser> createStereoDenoiser(std::string_view method) override {
    const MethodEntry* e = findMethod(method);
    if (e && e->createStereoCpu) return e->createStereoCpu(arena_);
    return std::make_unique<StereoPair>(createDenoiser(method), createDenoiser(method));
  }

 private:
  int threads_;
  tbb::task_arena& arena_;
};
}  // namespace

#ifdef RTD_HAS_VULKAN
std::unique_ptr<Device> createVulkanDevice(const DeviceDesc& desc);
std::vector<DeviceInfo> listVulkanDevices();
#endif

std::vector<DeviceInfo> listDevices(std::string* vulkanError) {
  std::vector<DeviceInfo> out;
  const int threads = tbb::info::default_concurrency();
  out.push_back({Backend::Cpu, 0, "CPU", std::to_string(threads) + " threads, oneTBB, SIMD path " + describeCpuPath()});
#ifdef RTD_HAS_VULKAN
  try {
    for (auto& d : listVulkanDevices()) out.push_back(std::move(d));
  } catch (const Error& e) {
    if (vulkanError) *vulkanError = e.what();
  }
#else
  if (vulkanError) *vulkanError = "this build of rtdenoise has no Vulkan backend (configure with -DRTD_VULKAN=ON)";
#endif
  return out;
}

std::unique_ptr<Device> Device::create(const DeviceDesc& desc) {
  if (desc.threads < 0 || desc.threads > 4096)
    throw Error("DeviceDesc::threads is " + std::to_string(desc.threads) + ", expected 0 (all cores) to 4096");
  if (desc.backend != Backend::Cpu && desc.backend != Backend::Vulkan)
    throw Error("DeviceDesc::backend " + std::to_string(int(desc.backend)) + " is not a backend");
  return guarded("Device::create", [&]() -> std::unique_ptr<Device> {
    if (desc.backend == Backend::Cpu) {
      checkCpuPathSetting();  // a bad RTD_CPU_PATH is an error here rather than silently ignored
      return std::make_unique<CpuDevice>(desc.threads);
    }
#ifdef RTD_HAS_VULKAN
    return createVulkanDevice(desc);
#else
    throw Error("this build of rtdenoise has no Vulkan backend (configure with -DRTD_VULKAN=ON)");
#endif
  });
}

}  // namespace rtd
