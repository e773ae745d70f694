// Test helper: the PyTorch cross-check fixture of TNND (testdata/, written by
// python/rtdenoise_train/fixture.py), as a frame for Denoiser::denoise and its expected output.
#pragma once
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "rtd/rtd.h"
#include "support/test_frames.h"

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
  auto planar = [&](const char* key) { return planarImage(j[key], w, h); };
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

}  // namespace rtd::test
