// Scratch folders, files, synthetic sequences and error messages, for the tests of files,
// sequences and the CLI.
#pragma once
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "rtd/sequence.h"
#include "rtd/error.h"
#include "synthetic/synthetic.h"

namespace rtd::test {

/// An empty folder `<prefix>_<name>_<pid>` in the system's temporary directory (whatever was
/// there is removed first): each test process gets its own.
inline std::filesystem::path scratchDir(const std::string& prefix, const std::string& name) {
  namespace fs = std::filesystem;
  fs::path p = fs::temp_directory_path() / (prefix + "_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

/// The message of the rtd::Error that `fn` throws; "" when it throws none. Any other exception
/// propagates, and fails the test that called this.
inline std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

/// The JSON document in file `p`.
inline nlohmann::json readJson(const std::filesystem::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

/// A native sequence of `frames` frames of the analytic scene at w x h in `dir`.
inline void writeSyntheticSequence(const std::filesystem::path& dir, int frames, int w = 24, int h = 16) {
  synthetic::Scene scene;
  scene.width = w;
  scene.height = h;
  SequenceWriter writer(dir);
  for (int k = 0; k < frames; ++k) writer.write(synthetic::makeFrame(scene, k));
  writer.finish();
}

}  // namespace rtd::test
