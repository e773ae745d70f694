// Helpers shared by the renderer tests: scenes from JSON text, pixel statistics.
#pragma once
#ifdef HAVE_RTDENOISE_RENDER
#include <unistd.h>

#include <array>
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

// Small double-precision vector helpers, independent of the renderer's code.
using Vec = std::array<double, 3>;
inline Vec sub(Vec a, Vec b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(Vec a, Vec b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec scale(Vec a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline Vec add(Vec a, Vec b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec norm(Vec a) { return scale(a, 1.0 / std::sqrt(dot(a, a))); }
inline Vec px3(const Image& img, int x, int y) { return {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)}; }

/// Pixel position of world point p through the stored matrices (OpenGL clip -> pixels, y down).
inline std::array<double, 2> projectWithMatrices(const Camera& c, Vec p, int w, int h) {
  double cam[4], clip[4];
  for (int r = 0; r < 4; ++r)
    cam[r] = c.worldToCamera[r * 4] * p[0] + c.worldToCamera[r * 4 + 1] * p[1] + c.worldToCamera[r * 4 + 2] * p[2] +
             c.worldToCamera[r * 4 + 3];
  for (int r = 0; r < 4; ++r)
    clip[r] = c.projection[r * 4] * cam[0] + c.projection[r * 4 + 1] * cam[1] + c.projection[r * 4 + 2] * cam[2] +
              c.projection[r * 4 + 3] * cam[3];
  return {(clip[0] / clip[3] * 0.5 + 0.5) * w, (0.5 - clip[1] / clip[3] * 0.5) * h};
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
