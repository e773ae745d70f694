// The C++ API in one program (docs/integration.md): the scene of examples/common/scene.h
// denoised frame by frame. Prints the error of the noisy input and of the denoised output
// against the clean image and the passes' times; fails unless denoising removed most of the noise.
//   example_denoise_cpp [method]      (default svgf)
#include <rtd/rtd.h>

#include <cstdio>
#include <string>
#include <vector>

#include "common/scene.h"

int main(int argc, char** argv) {
  const std::string method = argc > 1 ? argv[1] : "svgf";
  const int w = kSceneWidth, h = kSceneHeight;
  auto device = rtd::Device::create({.backend = rtd::Backend::Cpu});
  auto denoiser = device->createDenoiser(method);

  // The application's buffers: one view each, set once; their contents change every frame.
  std::vector<float> color(w * h * 3), clean(w * h * 3), albedo(w * h * 3), normal(w * h * 3), depth(w * h),
      motion(w * h * 2), output(w * h * 4);
  rtd::FrameInputs frame;
  frame[rtd::Buffer::Color] = {color.data(), w, h, rtd::Format::Float3};
  frame[rtd::Buffer::Albedo] = {albedo.data(), w, h, rtd::Format::Float3};
  frame[rtd::Buffer::Normal] = {normal.data(), w, h, rtd::Format::Float3};
  frame[rtd::Buffer::Depth] = {depth.data(), w, h, rtd::Format::Float};
  frame[rtd::Buffer::Motion] = {motion.data(), w, h, rtd::Format::Float2};
  const rtd::ImageView out{output.data(), w, h, rtd::Format::Float4};

  try {
    for (int t = 0; t < kSceneFrames; ++t) {
      sceneFrame(t, color.data(), clean.data(), albedo.data(), normal.data(), depth.data(), motion.data());
      denoiser->denoise(frame, out);  // on a camera cut: denoiser->reset() first
    }
  } catch (const rtd::Error& e) {
    std::fprintf(stderr, "rtdenoise: %s\n", e.what());
    return 1;
  }
  const double input = sceneRmse(color.data(), 3, clean.data()), result = sceneRmse(output.data(), 4, clean.data());
  std::printf("%s, %s: RMSE of frame %d: input %.4f, output %.4f\n", std::string(denoiser->method()).c_str(),
              device->name().c_str(), kSceneFrames, input, result);
  for (const auto& pass : denoiser->stats().passes) std::printf("  %-24s %8.3f ms\n", pass.name.c_str(), pass.milliseconds);
  return result < 0.5 * input ? 0 : 1;
}
