// Builds against the installed package and denoises two frames of a constant image.
#include <rtd/rtd.h>

#include <cmath>
#include <cstdio>

int main() {
  auto device = rtd::Device::create();
  auto denoiser = device->createDenoiser(rtd::AccumulateSettings{});
  rtd::Image color(8, 4, 3, 0.5f), out(8, 4, 3);
  rtd::FrameInputs frame;
  frame[rtd::Buffer::Color] = color.view();
  for (int i = 0; i < 2; ++i) denoiser->denoise(frame, out.view());
  for (float v : out.pixels)
    if (std::abs(v - 0.5f) > 1e-6f) return 1;
  std::printf("consumer ok: %s on %s\n", std::string(denoiser->method()).c_str(), device->name().c_str());
  return 0;
}
