// rtdenoise devices: the CPU and every Vulkan device, with the index or name --device takes.
#include "cli.h"

namespace rtd::cli {

void addDevices(CLI::App& app) {
  auto* cmd = app.add_subcommand("devices", "list the devices (CPU, Vulkan) denoisers can run on");
  cmd->callback([] {
    std::string vulkanError;
    const auto devices = listDevices(&vulkanError);
    for (const auto& d : devices) {
      if (d.backend == Backend::Cpu)
        std::printf("cpu             %s (%s)\n", d.name.c_str(), d.description.c_str());
      else
        std::printf("vulkan  --device %-3d %s (%s)\n", d.index, d.name.c_str(), d.description.c_str());
    }
    if (!vulkanError.empty()) std::printf("vulkan  unavailable: %s\n", vulkanError.c_str());
  });
}

}  // namespace rtd::cli
