// Issue 21: image views are checked identically on both backends before history is touched.
// Each malformed frame below must be refused with rtd::Error on the CPU and on Vulkan with the
// same message (the CPU used to accept pixel strides that are not a multiple of 4 and then do
// misaligned loads), and a denoiser that refused one keeps producing the outputs of one that
// never saw it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>

#include "rtd/rtd.h"
#include "support/backends.h"
#include "synthetic/synthetic.h"

namespace rtd::test {
namespace {

constexpr int kW = 24, kH = 16;

struct BadFrame {
  const char* what;
  const char* expect;  // part of the message
  std::function<void(FrameInputs&, ImageView& out, std::vector<char>& scratch)> edit;
};

std::vector<BadFrame> badFrames() {
  return {
      {"odd pixel stride", "multiples of 4",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(13) * kW * kH + 64, 0);
         in[Buffer::Color] = {m.data(), kW, kH, Format::Float3, 13};
       }},
      {"pixel stride 14", "multiples of 4",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(14) * kW * kH + 64, 0);
         in[Buffer::Normal] = {m.data(), kW, kH, Format::Float3, 14};
       }},
      {"row stride not a multiple of 4", "multiples of 4",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(12 * kW + 2) * kH + 64, 0);
         in[Buffer::Color] = {m.data(), kW, kH, Format::Float3, 0, size_t(12 * kW + 2)};
       }},
      {"half pixels with an odd stride", "multiples of 2",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(7) * kW * kH + 64, 0);
         in[Buffer::Color] = {m.data(), kW, kH, Format::Half3, 7};
       }},
      {"half pixels at an odd address", "not 2-byte aligned",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(6) * kW * kH + 64, 0);
         in[Buffer::Color] = {m.data() + 1, kW, kH, Format::Half3};
       }},
      {"pixel stride smaller than the format", "smaller than a pixel",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(8) * kW * kH + 64, 0);
         in[Buffer::Albedo] = {m.data(), kW, kH, Format::Float3, 8};
       }},
      {"row stride smaller than a row", "smaller than a row",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(12) * kW * kH + 64, 0);
         in[Buffer::Color] = {m.data(), kW, kH, Format::Float3, 0, size_t(12 * kW - 4)};
       }},
      {"misaligned pointer", "aligned",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(12) * kW * kH + 64, 0);
         in[Buffer::Color] = {m.data() + 2, kW, kH, Format::Float3};
       }},
      {"undefined format", "no format",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(12) * kW * kH, 0);
         in[Buffer::Depth] = {m.data(), kW, kH, Format::Undefined};
       }},
      {"too few channels", "needs 3 channels",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(8) * kW * kH, 0);
         in[Buffer::Normal] = {m.data(), kW, kH, Format::Float2};
       }},
      {"size differs from colour", "but color is",
       [](FrameInputs& in, ImageView&, std::vector<char>& m) {
         m.assign(size_t(4) * kW * kH, 0);
         in[Buffer::Depth] = {m.data(), kW - 1, kH, Format::Float};
       }},
      {"negative width", "empty size",
       [](FrameInputs& in, ImageView& out, std::vector<char>&) {
         in[Buffer::Color].width = -kW;
         out.width = -kW;
       }},
      {"huge size", "larger than the largest image",
       [](FrameInputs& in, ImageView& out, std::vector<char>&) {
         // No memory behind it: the size must be refused before anything reads or allocates.
         for (auto& v : in.buffers)
           if (!v.empty()) { v.width = 100000; v.height = 100000; }
         out.width = out.height = 100000;
       }},
      {"camera with NaN", "camera",
       [](FrameInputs& in, ImageView&, std::vector<char>&) {
         in.camera.valid = true;
         in.camera.projection[5] = std::nanf("");
       }},
      {"output of the wrong size", "output view is",
       [](FrameInputs&, ImageView& out, std::vector<char>&) { out.width = kW - 1; }},
      {"output Float2", "Float3, Float4, Half3 or Half4",
       [](FrameInputs&, ImageView& out, std::vector<char>&) { out.format = Format::Float2; }},
      {"output with an odd pixel stride", "multiples of 4",
       [](FrameInputs&, ImageView& out, std::vector<char>& m) {
         m.assign(size_t(15) * kW * kH + 64, 0);
         out = {m.data(), kW, kH, Format::Float3, 15};
       }},
      {"missing colour", "missing required buffer 'color'",
       [](FrameInputs& in, ImageView&, std::vector<char>&) { in[Buffer::Color] = {}; }},
  };
}

TEST(ViewValidation, BothBackendsRefuseTheSameFramesWithTheSameMessage) {
  synthetic::Scene scene;
  scene.width = kW;
  scene.height = kH;
  const Frame f0 = synthetic::makeFrame(scene, 0), f1 = synthetic::makeFrame(scene, 1), f2 = synthetic::makeFrame(scene, 2);
  for (const BadFrame& bad : badFrames()) {
    std::string messages[2];
    for (Backend backend : testBackends()) {
      Device* device = testDevice(backend);
      if (!device) continue;
      for (const char* method : {"accumulate", "svgf", "bmfr"}) {
        auto d = device->createDenoiser(method), clean = device->createDenoiser(method);
        Image out(kW, kH, 3), cleanOut(kW, kH, 3);
        d->denoise(f0.inputs(), out.view());
        clean->denoise(f0.inputs(), cleanOut.view());
        FrameInputs in = f1.inputs();
        ImageView view = out.view();
        std::vector<char> scratch;
        bad.edit(in, view, scratch);
        const std::string what = std::string(backendName(backend)) + " " + method + ": " + bad.what;
        try {
          d->denoise(in, view);
          ADD_FAILURE() << what << " was accepted";
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find(bad.expect), std::string::npos) << what << ": " << e.what();
          std::string& m = messages[backend == Backend::Cpu ? 0 : 1];
          if (m.empty()) m = e.what();
          else EXPECT_EQ(m, e.what()) << what << ": methods disagree";
        } catch (const std::exception& e) {
          ADD_FAILURE() << what << ": not an rtd::Error: " << e.what();
        }
        // History untouched: the next good frame gives what a denoiser without the bad one gives.
        d->denoise(f2.inputs(), out.view());
        clean->denoise(f2.inputs(), cleanOut.view());
        EXPECT_EQ(out.pixels, cleanOut.pixels) << what;
      }
    }
    if (!messages[0].empty() && !messages[1].empty()) { EXPECT_EQ(messages[0], messages[1]) << bad.what; }
  }
}

// Strided views that are well formed are accepted by both and give the same outputs as packed ones.
TEST(ViewValidation, WellFormedStridesAreAccepted) {
  synthetic::Scene scene;
  scene.width = kW;
  scene.height = kH;
  const Frame f = synthetic::makeFrame(scene, 0);
  for (Backend backend : testBackends()) {
    Device* device = testDevice(backend);
    if (!device) continue;
    auto packed = device->createDenoiser("accumulate"), strided = device->createDenoiser("accumulate");
    Image a(kW, kH, 3), b(kW, kH, 4);
    packed->denoise(f.inputs(), a.view());
    // Colour as 5 floats per pixel with a padded row.
    const size_t rowFloats = size_t(kW) * 5 + 3;
    std::vector<float> color(rowFloats * kH, -1.0f);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        for (int c = 0; c < 3; ++c) color[y * rowFloats + size_t(x) * 5 + c] = f[Buffer::Color].at(x, y, c);
    FrameInputs in = f.inputs();
    in[Buffer::Color] = {color.data(), kW, kH, Format::Float3, 20, rowFloats * 4};
    strided->denoise(in, b.view());
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(b.at(x, y, c), a.at(x, y, c)) << backendName(backend);
  }
}

}  // namespace
}  // namespace rtd::test
