// Test helper: the PyTorch cross-check fixtures of the RAE (testdata/rae_fixture_<inputs>.json,
// written by python/rtdenoise_train/fixture.py: random weights, 21x13 frames, three frames
// with the hidden state carried, frames 1 and 2 identical), as frames for Denoiser::denoise and
// their expected outputs. Used by the CPU (rae_test.cpp) and Vulkan (tests/vulkan) tests.
#pragma once
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "rtd/rtd.h"
#include "support/test_frames.h"

namespace rtd::test {

struct RaeFixture {
  std::vector<Frame> frames;
  std::vector<Image> expected;  ///< radiance computed by PyTorch in float64, per frame
  std::string weights;          ///< path of the fixture's weights file
};

/// `inputs`: "color_albedo_normal" or "color".
inline RaeFixture loadRaeFixture(const std::string& inputs) {
  const std::string dir = std::string(RTD_SOURCE_DIR) + "/src/methods/rae/testdata/";
  std::ifstream in(dir + "rae_fixture_" + inputs + ".json");
  std::stringstream ss;
  ss << in.rdbuf();
  const auto j = nlohmann::json::parse(ss.str());
  const int w = j["width"], h = j["height"];
  RaeFixture f;
  f.weights = dir + j["weights"].get<std::string>();
  for (size_t t = 0; t < j["color"].size(); ++t) {
    Frame frame;
    frame.width = w;
    frame.height = h;
    frame[Buffer::Color] = planarImage(j["color"][t], w, h);
    frame[Buffer::Albedo] = planarImage(j["albedo"], w, h);
    frame[Buffer::Normal] = planarImage(j["normal"], w, h);
    for (int i = 0; i < 16; ++i) frame.camera.worldToCamera[size_t(i)] = j["worldToCamera"][size_t(i)].get<float>();
    frame.camera.valid = true;
    f.frames.push_back(frame);
    f.expected.push_back(planarImage(j["expected"][t], w, h));
  }
  return f;
}

}  // namespace rtd::test
