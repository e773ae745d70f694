// Test helper: the PyTorch cross-check fixture of TNND (testdata/, written by
// python/rtdenoise_train/fixture.py), as a frame for Denoiser::denoise and its expected output.
#pragma once
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "rtd/rtd.h"

namespace rtd::test {

struct TnndFixture {
  Frame frame;
  std::string weights;  ///< path of the fixture's weights file
  int iterations = 0;
  Image expected;       ///< radiance RGB computed by PyTorch in float64
};

inline TnndFixture loadTnndFixture() {
  const std::string dir = std::string(RTD_SOURCE_DIR) + "/src/methods/tnnd/testdata/";
  std::ifstream in(dir + "tnnd_fixture.json");
  std::stringstream ss;
  ss << in.rdbuf();
  const auto j = nlohmann::json::parse(ss.str());
  TnndFixture f;
  const int w = j["width"], h = j["height"];
  f.iterations = j["iterations"];
  f.weights = dir + j["weights"].get<std::string>();
  auto planar = [&](const char* key) {  // [c][y][x] -> interleaved image
    const auto& a = j[key];
    const int channels = int(a.size()) / (w * h);
    Image img(w, h, channels);
    for (int c = 0; c < channels; ++c)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(x, y, c) = a[(size_t(c) * h + y) * w + x].get<float>();
    return img;
  };
  f.frame.width = w;
  f.frame.height = h;
  f.frame[Buffer::Color] = planar("color");
  f.frame[Buffer::Normal] = planar("normal");
  f.frame[Buffer::Albedo] = planar("albedo");
  for (int i = 0; i < 16; ++i) f.frame.camera.worldToCamera[i] = j["worldToCamera"][i].get<float>();
  f.frame.camera.valid = true;
  f.expected = planar("expected");
  return f;
}

/// Largest |a - e| / (1 + |e|) over all values.
inline double maxRelativeError(const Image& a, const Image& e) {
  double m = 0;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x)
      for (int c = 0; c < 3; ++c)
        m = std::max(m, std::abs(double(a.at(x, y, c)) - e.at(x, y, c)) / (1.0 + std::abs(double(e.at(x, y, c)))));
  return m;
}

}  // namespace rtd::test
