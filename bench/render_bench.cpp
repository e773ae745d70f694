// Path tracer benchmarks: one frame of a built-in scene at 1 spp with every feature buffer, and
// the reference path (no features). Reports rays per second as a counter.
#ifdef HAVE_RTDENOISE_RENDER
#include <benchmark/benchmark.h>

#include <ctime>

#include "rtd/render/render.h"

namespace {

void renderFrame(benchmark::State& state, const char* sceneName, int w, int h) {
  auto scene = rtd::render::Scene::load(sceneName);
  rtd::render::RenderSettings s = scene->suggestedSettings();
  s.width = w;
  s.height = h;
  rtd::render::Renderer r(scene, s);
  r.render(0);  // builds the geometry once
  uint64_t rays = 0;
  double seconds = 0;
  // Process CPU time (all threads): on a loaded machine, cpu / cores bounds the unloaded wall time.
  const std::clock_t cpuStart = std::clock();
  for (auto _ : state) {
    rtd::Frame f = r.render(1);
    benchmark::DoNotOptimize(f.buffers[0].pixels.data());
    rays += r.stats().rays;
    seconds += r.stats().seconds;
  }
  state.counters["Mrays/s"] = seconds > 0 ? double(rays) / seconds * 1e-6 : 0.0;
  state.counters["rays/frame"] = double(rays) / double(state.iterations());
  state.counters["cpu_s/frame"] = double(std::clock() - cpuStart) / CLOCKS_PER_SEC / double(state.iterations());
}

void BM_RenderFrame720p(benchmark::State& state, const char* scene) { renderFrame(state, scene, 1280, 720); }
void BM_RenderFrame180p(benchmark::State& state, const char* scene) { renderFrame(state, scene, 320, 180); }

void BM_Reference180p(benchmark::State& state) {
  auto scene = rtd::render::Scene::load("dynamic");
  rtd::render::Renderer r(scene, scene->suggestedSettings());
  for (auto _ : state) {
    rtd::Image img = r.renderReference(0, int(state.range(0)));
    benchmark::DoNotOptimize(img.pixels.data());
  }
  state.counters["Mrays/s"] = r.stats().raysPerSecond() * 1e-6;
}

}  // namespace

BENCHMARK_CAPTURE(BM_RenderFrame720p, cornell, "cornell")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame720p, pillars, "pillars")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame720p, glossy, "glossy")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame720p, dynamic, "dynamic")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame180p, dynamic, "dynamic")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Reference180p)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();
#endif
