// Google Benchmark: SVGF at 1280x720 on the synthetic scene, whole method per variant and the
// a-trous level alone. The *_1thread cases run in a one-thread arena, so their CPU time is
// the work itself (stable on a shared machine); the 2-thread cases give wall time.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "core/cpu_path.h"
#include "passes/atrous.h"
#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

namespace {

constexpr int kW = 1280, kH = 720;

void BM_Svgf(benchmark::State& state, const char* variant, int threads) {
  rtd::synthetic::Scene scene;
  scene.width = kW;
  scene.height = kH;
  std::vector<rtd::Frame> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(rtd::synthetic::makeFrame(scene, i));
  auto device = rtd::Device::create({.threads = threads});
  auto d = device->createDenoiser("svgf");
  d->set("variant", variant);
  rtd::Image out(kW, kH, 3);
  for (int i = 0; i < 4; ++i) d->denoise(frames[i].inputs(), out.view());  // build history
  int i = 0;
  for (auto _ : state) {
    const int k = i++ % 6, idx = k < 4 ? k : 6 - k;  // 0,1,2,3,2,1: one camera step apart
    d->denoise(frames[idx].inputs(), out.view());
    benchmark::DoNotOptimize(out.pixels.data());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(kW) * kH);
}
BENCHMARK_CAPTURE(BM_Svgf, schied_2threads, "schied", 2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Svgf, dundr_2threads, "dundr", 2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Svgf, gersthofer_2threads, "gersthofer", 2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Svgf, voorhuis_2threads, "voorhuis", 2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Svgf, schied_1thread, "schied", 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Svgf, dundr_1thread, "dundr", 1)->Unit(benchmark::kMillisecond);

// A frame right after a reset: every pixel has a short history, so the spatial variance
// estimate (7x7 window) runs everywhere -- the worst case, e.g. after a camera cut.
void BM_SvgfAfterReset(benchmark::State& state, const char* variant) {
  rtd::synthetic::Scene scene;
  scene.width = kW;
  scene.height = kH;
  const rtd::Frame f = rtd::synthetic::makeFrame(scene, 0);
  auto device = rtd::Device::create({.threads = 1});
  auto d = device->createDenoiser("svgf");
  d->set("variant", variant);
  rtd::Image out(kW, kH, 3);
  d->denoise(f.inputs(), out.view());
  for (auto _ : state) {
    d->reset();
    d->denoise(f.inputs(), out.view());
    benchmark::DoNotOptimize(out.pixels.data());
  }
}
BENCHMARK_CAPTURE(BM_SvgfAfterReset, schied_1thread, "schied")->Unit(benchmark::kMillisecond);

// One a-trous level (with variance propagation) on flat-ish features and noisy colour; args:
// the step, the CPU path (0 sse2, 1 avx2, 2 avx512; -1 the current one, RTD_CPU_PATH) and the
// height (width 16:9; default 720): at 180 the planes fit in the caches, so the time per pixel
// against 720's says how much of the level waits on memory.
void BM_AtrousLevel(benchmark::State& state, rtd::AtrousKernel kernel, int threads) {
  const int step = int(state.range(0));
  const int path = int(state.range(1));
  const int h = state.range(2) > 0 ? int(state.range(2)) : 720, w = h * 16 / 9;
  if (path >= 0 && !rtd::cpuPathSupported(rtd::CpuPath(path))) {
    state.SkipWithError("this CPU lacks the path");
    return;
  }
  const rtd::CpuPath previous = path >= 0 ? rtd::setCpuPath(rtd::CpuPath(path)) : rtd::cpuPath();
  rtd::AtrousGuide g;
  rtd::AtrousImage a, b;
  rtd::PaddedPlane inv;
  g.resize(w, h, 32);
  a.resize(w, h, 32);
  b.resize(w, h, 32);
  inv.resize(w, h, 32);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      g.depth.at(x, y) = 5.0f + 0.001f * y;
      g.gradY.at(x, y) = 0.001f;
      g.normal[2].at(x, y) = 1.0f;
      const float v = float((x * 7919 + y * 104729) % 97) / 97.0f;
      for (auto& c : a.color) c.at(x, y) = v;
      a.lum.at(x, y) = v;
      a.var.at(x, y) = 0.1f;
      inv.at(x, y) = 1.0f;  // sigma_l multiplier
    }
  rtd::AtrousLevel lv;
  lv.kernel = kernel;
  lv.step = step;
  lv.sigmaScale = &inv;
  tbb::task_arena arena(threads);
  for (auto _ : state) {
    arena.execute([&] { rtd::atrousLevel(g, lv, a, b); });
    benchmark::DoNotOptimize(b.color[0].data.data());
  }
  rtd::setCpuPath(previous);
  state.SetItemsProcessed(state.iterations() * int64_t(w) * h);
}
BENCHMARK_CAPTURE(BM_AtrousLevel, b3spline5x5_1thread, rtd::AtrousKernel::B3Spline5x5, 1)
    ->ArgsProduct({{1, 2, 4, 8, 16}, {0, 1, 2}, {720, 180}})->ArgNames({"step", "path", "height"})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_AtrousLevel, binomial3x3_1thread, rtd::AtrousKernel::Binomial3x3, 1)
    ->ArgsProduct({{1, 2, 4, 8, 16}, {0, 1, 2}, {720, 180}})->ArgNames({"step", "path", "height"})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_AtrousLevel, b3spline5x5_2threads, rtd::AtrousKernel::B3Spline5x5, 2)
    ->Args({1, -1, 720})->Args({16, -1, 720})->ArgNames({"step", "path", "height"})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
