// The list of methods and how each backend creates them.
#pragma once
#include <memory>
#include <vector>

#include "rtd/denoiser.h"
#include "rtd/stereo.h"

#include <tbb/task_arena.h>

namespace rtd {

namespace vk { class Context; }

struct MethodEntry {
  const char* name;
  const char* summary;
  std::vector<SettingInfo> (*defaults)();
  std::unique_ptr<Denoiser> (*createCpu)(tbb::task_arena&);   // null if not on the CPU
  std::unique_ptr<Denoiser> (*createVulkan)(vk::Context&);    // null if not on Vulkan
  /// Two-view pipelines (rtd/stereo.h); null: a StereoPair of two single-view denoisers.
  std::unique_ptr<StereoDenoiser> (*createStereoCpu)(tbb::task_arena&) = nullptr;
  std::unique_ptr<StereoDenoiser> (*createStereoVulkan)(vk::Context&) = nullptr;
};

const std::vector<MethodEntry>& methodRegistry();
const MethodEntry* findMethod(std::string_view name);

}  // namespace rtd
