// Cost of the evaluation metrics per frame (tone-mapped 640x360 and 1280x720 images), to size
// the demo and comparison runs.
#include <benchmark/benchmark.h>

#include "rtd/eval/evaluate.h"
#include "synthetic/synthetic.h"

namespace {
struct Pair {
  rtd::Image noisy, reference, noisyLdr, referenceLdr;
};
Pair makePair(int w, int h) {
  rtd::synthetic::Scene scene;
  scene.width = w;
  scene.height = h;
  Pair p;
  rtd::Frame f = rtd::synthetic::makeFrame(scene, 3, &p.reference);
  p.noisy = f[rtd::Buffer::Color];
  p.noisyLdr = rtd::eval::toneMap(p.noisy);
  p.referenceLdr = rtd::eval::toneMap(p.reference);
  return p;
}

void BM_Ssim(benchmark::State& st) {
  const Pair p = makePair(int(st.range(0)), int(st.range(1)));
  for (auto _ : st) benchmark::DoNotOptimize(rtd::eval::ssim(p.noisyLdr, p.referenceLdr));
}
void BM_Flip(benchmark::State& st) {
  const Pair p = makePair(int(st.range(0)), int(st.range(1)));
  for (auto _ : st) benchmark::DoNotOptimize(rtd::eval::flip(p.noisyLdr, p.referenceLdr));
}
void BM_FlipPreparedReference(benchmark::State& st) {
  const Pair p = makePair(int(st.range(0)), int(st.range(1)));
  const rtd::eval::FlipReference ref(p.referenceLdr);
  for (auto _ : st) benchmark::DoNotOptimize(ref.compare(p.noisyLdr));
}
// Everything one stream costs per frame in a comparison (reference prepared once, outside).
void BM_EvaluateFrame(benchmark::State& st) {
  const Pair p = makePair(int(st.range(0)), int(st.range(1)));
  const auto prepared = rtd::eval::prepareReference(1, p.reference, {});
  rtd::eval::SequenceEvaluator ev;
  for (auto _ : st) benchmark::DoNotOptimize(ev.add(p.noisy, prepared).psnr);
}
}  // namespace

BENCHMARK(BM_Ssim)->Args({640, 360})->Args({1280, 720})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Flip)->Args({640, 360})->Args({1280, 720})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FlipPreparedReference)->Args({640, 360})->Args({1280, 720})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EvaluateFrame)->Args({640, 360})->Args({1280, 720})->Unit(benchmark::kMillisecond);
