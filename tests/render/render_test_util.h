// Helpers shared by the renderer tests: scenes from JSON text, pixel statistics.
#pragma once
#ifdef HAVE_RTDENOISE_RENDER
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tbb/task_arena.h>

#include "rtd/render/render.h"

namespace rtd::render::test {

inline std::shared_ptr<Scene> sceneFromJson(const std::string& text) {
  return Scene::fromJson(text, std::filesystem::current_path(), "test.json");
}

inline double luminanceOf(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

inline RenderSettings tiny(int w, int h, int spp = 1) {
  RenderSettings s;
  s.width = w;
  s.height = h;
  s.spp = spp;
  return s;
}

/// Runs fn inside an arena of `threads` workers (thread-count independence checks).
template <class Fn> auto withThreads(int threads, Fn&& fn) {
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<Fn>(fn));
}

inline std::filesystem::path tempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("rtd_render_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Runs the `rtdenoise` command with `args`; its stdout and stderr go to `output`.
inline int runCli(const std::string& args, std::string& output) {
  const auto log = std::filesystem::temp_directory_path() / ("rtd_render_cli_" + std::to_string(::getpid()) + ".log");
  const int rc = std::system((std::string(RTD_CLI) + " " + args + " > " + log.string() + " 2>&1").c_str());
  std::ifstream in(log);
  std::stringstream ss;
  ss << in.rdbuf();
  output = ss.str();
  std::filesystem::remove(log);
  return rc;
}

}  // namespace rtd::render::test
#endif
