// Google Benchmark: BMFR's per-block QR (the whole method is in bench/methods_bench.cpp).
// Per-phase figures come from `rtdenoise bench --method bmfr --size 1280x720`.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "methods/bmfr/qr.h"
#include "rtd/rtd.h"

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
BENCHMARK(BM_BmfrBlockQr)->Args({256, 10})->Args({1024, 10})->Args({4096, 10})->Args({1024, 12})->Unit(benchmark::kMicrosecond);

// The same block as 512-row tiles (what the pipeline runs): each tile's reflections stay in L1.
void BM_BmfrBlockQrTiled(benchmark::State& state) {
  const int rows = int(state.range(0)), features = int(state.range(1)), columns = features + 3, tileRows = 512;
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


}  // namespace
