// The C++ API in one program (docs/integration.md): a textured wall scrolling one pixel per
// frame, rendered with 1-spp-like noise, denoised frame by frame. Prints the error of the noisy
// input and of the denoised output against the clean image, and the passes' times; fails
// unless denoising removed most of the noise.
//   denoise_cpp [method]      (default svgf)
#include <rtd/rtd.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

constexpr int W = 64, H = 48, kFrames = 8;

// The scene at frame t: albedo (a checkerboard), light (a smooth gradient), both scrolling right.
float albedoAt(int x, int y, int t) { return ((x - t + 64) / 8 + y / 8) % 2 ? 0.8f : 0.2f; }
float lightAt(int x, int y, int t) { return 1.0f + 0.5f * std::sin(0.1f * float(x - t)) * std::cos(0.13f * float(y)); }
// 1-spp-like noise: an exponential variate of mean 1 from a hash of (pixel, frame).
float noiseAt(int x, int y, int t) {
  unsigned h = unsigned(x) * 73856093u ^ unsigned(y) * 19349663u ^ unsigned(t) * 83492791u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return -std::log((float((h >> 8) & 0xffffff) + 0.5f) / 16777216.0f);
}

int main(int argc, char** argv) {
  const std::string method = argc > 1 ? argv[1] : "svgf";
  auto device = rtd::Device::create({.backend = rtd::Backend::Cpu});
  auto denoiser = device->createDenoiser(method);

  // The application's buffers: one view each, set once; their contents change every frame.
  std::vector<float> color(W * H * 3), albedo(W * H * 3), normal(W * H * 3), depth(W * H), motion(W * H * 2);
  std::vector<float> clean(W * H * 3), output(W * H * 4);
  rtd::FrameInputs frame;
  frame[rtd::Buffer::Color] = {color.data(), W, H, rtd::Format::Float3};
  frame[rtd::Buffer::Albedo] = {albedo.data(), W, H, rtd::Format::Float3};
  frame[rtd::Buffer::Normal] = {normal.data(), W, H, rtd::Format::Float3};
  frame[rtd::Buffer::Depth] = {depth.data(), W, H, rtd::Format::Float};
  frame[rtd::Buffer::Motion] = {motion.data(), W, H, rtd::Format::Float2};
  const rtd::ImageView out{output.data(), W, H, rtd::Format::Float4};

  double inputError = 0, outputError = 0;
  for (int t = 0; t < kFrames; ++t) {
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int p = y * W + x;
        for (int c = 0; c < 3; ++c) {
          albedo[p * 3 + c] = albedoAt(x, y, t);
          clean[p * 3 + c] = albedoAt(x, y, t) * lightAt(x, y, t);
          color[p * 3 + c] = clean[p * 3 + c] * noiseAt(x, y, t);
          normal[p * 3 + c] = c == 2 ? 1.0f : 0.0f;  // world-space, facing the camera
        }
        depth[p] = 5.0f;        // linear view depth
        motion[p * 2] = -1.0f;  // the content of pixel x was at x - 1 in the previous frame
        motion[p * 2 + 1] = 0.0f;
      }
    denoiser->denoise(frame, out);
    inputError = outputError = 0;
    for (int p = 0; p < W * H; ++p)
      for (int c = 0; c < 3; ++c) {
        inputError += std::pow(color[p * 3 + c] - clean[p * 3 + c], 2);
        outputError += std::pow(output[p * 4 + c] - clean[p * 3 + c], 2);
      }
  }
  inputError = std::sqrt(inputError / (W * H * 3));
  outputError = std::sqrt(outputError / (W * H * 3));
  std::printf("%s, %s: RMSE of frame %d: input %.4f, output %.4f\n", denoiser->method().data(), device->name().c_str(),
              kFrames, inputError, outputError);
  for (const auto& pass : denoiser->stats().passes) std::printf("  %-24s %8.3f ms\n", pass.name.c_str(), pass.milliseconds);
  return outputError < 0.5 * inputError ? 0 : 1;
}
