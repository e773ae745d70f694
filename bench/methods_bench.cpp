// Google Benchmark: whole methods at 1280x720 on the synthetic scene, through the public API
// (per-pass figures come from `rtdenoise bench`; method-specific kernels in src/methods/*/ *_bench.cpp).
#include <benchmark/benchmark.h>

#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

namespace {

// Whole-method timings through the public API; per-pass figures come from `rtdenoise bench`.
void BM_Method(benchmark::State& state, const char* method) {
  rtd::synthetic::Scene scene;
  scene.width = 1280;
  scene.height = 720;
  const rtd::Frame a = rtd::synthetic::makeFrame(scene, 0), b = rtd::synthetic::makeFrame(scene, 1);
  auto device = rtd::Device::create();
  auto denoiser = device->createDenoiser(method);
  rtd::Image out(scene.width, scene.height, 3);
  int i = 0;
  for (auto _ : state) {
    denoiser->denoise((i++ & 1 ? b : a).inputs(), out.view());
    benchmark::DoNotOptimize(out.pixels.data());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(scene.width) * scene.height);
}
BENCHMARK_CAPTURE(BM_Method, accumulate, "accumulate")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Method, bmfr, "bmfr")->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
