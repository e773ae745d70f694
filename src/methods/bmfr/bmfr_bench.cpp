// Google Benchmark: BMFR's per-block QR and the whole method at 1280x720 on the synthetic scene.
// Per-phase figures come from `rtdenoise bench --method bmfr --size 1280x720`.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "methods/bmfr/qr.h"
#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

namespace {

// One block: `rows` x (features + 3) column-major, QR + back substitution. The columns are
// restored from a copy each iteration (the QR works in place); the copy is part of the time.
void BM_BmfrBlockQr(benchmark::State& state) {
  const int rows = int(state.range(0)), features = int(state.range(1)), columns = features + 3;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> source(size_t(rows) * columns), work(source.size());
  for (auto& v : source) v = u(rng);
  for (int r = 0; r < rows; ++r) source[r] = 1.0f;
  rtd::bmfr::TriangularSystem system;
  float alpha[rtd::bmfr::kMaxChannels][rtd::bmfr::kMaxFeatures];
  for (auto _ : state) {
    work = source;
    rtd::bmfr::householderQr(work.data(), rows, size_t(rows), features, 3, system);
    rtd::bmfr::backSubstitute(system, alpha);
    benchmark::DoNotOptimize(alpha);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BmfrBlockQr)->Args({1024, 10})->Args({4096, 10})->Args({1024, 12})->Unit(benchmark::kMicrosecond);

// The same block as 256-row tiles (what the pipeline runs): each tile's reflections stay in L1.
void BM_BmfrBlockQrTiled(benchmark::State& state) {
  const int rows = int(state.range(0)), features = int(state.range(1)), columns = features + 3, tileRows = 256;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> source(size_t(rows) * columns), work(source.size());
  for (auto& v : source) v = u(rng);
  for (int t = 0; t < rows / tileRows; ++t)
    for (int r = 0; r < tileRows; ++r) source[size_t(t) * columns * tileRows + r] = 1.0f;
  rtd::bmfr::TriangularSystem system;
  float alpha[rtd::bmfr::kMaxChannels][rtd::bmfr::kMaxFeatures];
  for (auto _ : state) {
    work = source;
    rtd::bmfr::householderQrTiled(work.data(), rows, tileRows, tileRows, features, 3, system);
    rtd::bmfr::backSubstitute(system, alpha);
    benchmark::DoNotOptimize(alpha);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BmfrBlockQrTiled)->Args({1024, 10})->Args({4096, 10})->Args({1024, 12})->Unit(benchmark::kMicrosecond);

void BM_BmfrMethod(benchmark::State& state) {
  rtd::synthetic::Scene scene;
  scene.width = 1280;
  scene.height = 720;
  const rtd::Frame a = rtd::synthetic::makeFrame(scene, 0), b = rtd::synthetic::makeFrame(scene, 1);
  auto device = rtd::Device::create();
  auto denoiser = device->createDenoiser("bmfr");
  rtd::Image out(scene.width, scene.height, 3);
  int i = 0;
  for (auto _ : state) {
    denoiser->denoise((i++ & 1 ? b : a).inputs(), out.view());
    benchmark::DoNotOptimize(out.pixels.data());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(scene.width) * scene.height);
}
BENCHMARK(BM_BmfrMethod)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
