// Builds against the installed package (no C++ standard set by this project) and denoises two
// frames of a constant image; uses the eval component and, where installed, render and vulkan.
#include <rtd/eval/metrics.h>
#include <rtd/rtd.h>
#if RTD_WITH_RENDER
#include <rtd/render/render.h>
#endif
#if RTD_WITH_VULKAN
#include <rtd/vulkan.h>
#endif

#include <cmath>
#include <cstdio>
#include <cstring>

static_assert(RTD_WITH_VULKAN == CONSUMER_PACKAGE_VULKAN, "rtd/config.h and the CMake package disagree on Vulkan");

int main() {
  if (std::strcmp(rtd::versionString(), RTD_VERSION_STRING) != 0) {
    std::printf("headers are %s, library is %s\n", RTD_VERSION_STRING, rtd::versionString());
    return 1;
  }
  auto device = rtd::Device::create();
  auto denoiser = device->createDenoiser(rtd::AccumulateSettings{});
  rtd::Image color(8, 4, 3, 0.5f), out(8, 4, 3);
  rtd::FrameInputs frame;
  frame[rtd::Buffer::Color] = color.view();
  for (int i = 0; i < 2; ++i) denoiser->denoise(frame, out.view());
  for (float v : out.pixels)
    if (std::abs(v - 0.5f) > 1e-6f) return 1;
  // A constant image denoised to itself: RMSE 0.
  if (rtd::eval::rmse(out, color) != 0.0) return 1;
#if RTD_WITH_RENDER
  if (rtd::render::Scene::builtinScenes().empty()) return 1;
#endif
  std::printf("consumer ok: rtdenoise %s, %s on %s, vulkan %s\n", rtd::versionString(),
              std::string(denoiser->method()).c_str(), device->name().c_str(), RTD_WITH_VULKAN ? "yes" : "no");
  return 0;
}
