// Device::create and the CPU device: a oneTBB arena that every CPU denoiser runs in.
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "core/registry.h"
#include "rtd/denoiser.h"

namespace rtd {

namespace {
class CpuDevice final : public Device {
 public:
  explicit CpuDevice(int threads)
      : arena_(threads > 0 ? threads : tbb::info::default_concurrency()),
        threads_(threads > 0 ? threads : tbb::info::default_concurrency()) {}
  Backend backend() const override { return Backend::Cpu; }
  std::string name() const override { return "CPU (" + std::to_string(threads_) + " threads, oneTBB)"; }
  std::unique_ptr<Denoiser> createDenoiser(std::string_view method) override {
    const MethodEntry* e = findMethod(method);
    if (!e) throw Error("unknown method '" + std::string(method) + "' (see `rtdenoise methods`)");
    if (!e->createCpu) throw Error("method '" + std::string(method) + "' has no CPU implementation");
    return e->createCpu(arena_);
  }

 private:
  tbb::task_arena arena_;
  int threads_;
};
}  // namespace

#ifdef RTD_HAS_VULKAN
std::unique_ptr<Device> createVulkanDevice(const DeviceDesc& desc);
#endif

std::unique_ptr<Device> Device::create(const DeviceDesc& desc) {
  if (desc.backend == Backend::Cpu) return std::make_unique<CpuDevice>(desc.threads);
#ifdef RTD_HAS_VULKAN
  return createVulkanDevice(desc);
#else
  throw Error("this build of rtdenoise has no Vulkan backend (configure with -DRTD_VULKAN=ON)");
#endif
}

}  // namespace rtd
