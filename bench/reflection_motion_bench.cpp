// Google Benchmark: Voorhuis's reflection motion vectors (specularReprojection: the diamond
// search of Algorithm 1 and its subpixel fit at every Mirror and GlossyReflection pixel) on two
// consecutive rendered 640x360 frames of a built-in scene, one thread (CPU time). Items are the
// searched pixels; the counter `taps/pixel` is the distance evaluations per searched pixel.
#ifdef HAVE_RTDENOISE_RENDER
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "core/frame_data.h"
#include "passes/reflection_reprojection.h"
#include "rtd/render/render.h"

namespace {

constexpr int kW = 640, kH = 360;

void BM_SpecularReprojection(benchmark::State& state, const char* sceneName) {
  auto scene = rtd::render::Scene::load(sceneName);
  rtd::render::RenderSettings s = scene->suggestedSettings();
  s.width = kW;
  s.height = kH;
  rtd::render::Renderer r(scene, s);
  rtd::FrameData prev, cur;
  rtd::importFrame(r.render(2).inputs(), {rtd::Buffer::Color}, prev);
  rtd::importFrame(r.render(3).inputs(), {rtd::Buffer::Color}, cur);
  rtd::PixelVector<uint8_t> cls, prevCls;
  rtd::classifySurfaces(cur, {}, false, cls);
  rtd::classifySurfaces(prev, {}, false, prevCls);
  rtd::Reprojection primary, out;
  rtd::reproject(cur, &prev, {}, primary);
  rtd::ReflectionSearchFeatures features;
  rtd::ReflectionMotionStats stats;
  tbb::task_arena arena(1);
  for (auto _ : state)
    arena.execute([&] {
      rtd::specularReprojection(cur, &prev, cls, prevCls, primary, rtd::SpecularMotion::Reflection, {}, out, &stats,
                                &features);
    });
  const uint64_t searched = stats.mirrorPixels + stats.glossyPixels;
  state.SetItemsProcessed(state.iterations() * int64_t(searched));
  state.counters["mirror px"] = double(stats.mirrorPixels);
  state.counters["glossy px"] = double(stats.glossyPixels);
  state.counters["taps/pixel"] = searched ? double(stats.taps) / double(searched) : 0.0;
}

}  // namespace

BENCHMARK_CAPTURE(BM_SpecularReprojection, mirrorfloor, "mirrorfloor")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SpecularReprojection, glossy, "glossy")->Unit(benchmark::kMillisecond);
#endif
