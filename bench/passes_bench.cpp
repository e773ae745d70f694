// Google Benchmark: the shared temporal passes alone at 1280x720 on the synthetic scene, one
// thread (CPU time, stable on a shared machine), per CPU path: reprojection (src/passes/
// reprojection.h), temporal accumulation of colour and moments (temporal_accumulation.h) and
// TAA (taa.h), each on frame 1 with frame 0 as the previous frame. Args: the CPU path (0 sse2,
// 1 avx2, 2 avx512), as in BM_AtrousLevel (src/methods/svgf/svgf_bench.cpp).
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "core/cpu_path.h"
#include "core/frame_data.h"
#include "passes/reprojection.h"
#include "passes/taa.h"
#include "passes/temporal_accumulation.h"
#include "rtd/methods/bmfr.h"
#include "rtd/rtd.h"
#include "synthetic/synthetic.h"

namespace {

constexpr int kW = 1280, kH = 720;

// Two consecutive frames of the synthetic scene (camera one step apart), imported, and the
// reprojection of the second onto the first; built once.
struct Inputs {
  rtd::FrameData previous, current;
  rtd::Reprojection reprojection;
  rtd::Plane3 color;
  Inputs() {
    rtd::synthetic::Scene scene;
    scene.width = kW;
    scene.height = kH;
    rtd::importFrame(rtd::synthetic::makeFrame(scene, 0).inputs(), {rtd::Buffer::Color}, previous);
    rtd::importFrame(rtd::synthetic::makeFrame(scene, 1).inputs(), {rtd::Buffer::Color}, current);
    rtd::reproject(current, &previous, {}, reprojection);
    for (int c = 0; c < 3; ++c) color[size_t(c)] = current.plane(rtd::Buffer::Color, c);
  }
};
const Inputs& inputs() {
  static const Inputs in;
  return in;
}

// The same frames with a jittered motion field (2.3 +- 0.8, -0.6 +- 0.4 pixels, a hash per
// pixel): the eight footprints of a group are rarely consecutive but lie in one row within 16
// elements, as with per-pixel jittered or noisy motion vectors: Bilinear8 gathers.
const Inputs& jitteredInputs() {
  static const Inputs in = [] {
    Inputs j;
    rtd::Plane mx(kW, kH), my(kW, kH);
    uint32_t state = 2024;
    auto next = [&] {
      state = state * 1664525u + 1013904223u;
      return float(state >> 8) / 16777216.0f;
    };
    for (size_t i = 0; i < mx.data.size(); ++i) {
      mx.data[i] = 2.3f + 1.6f * next() - 0.8f;
      my.data[i] = -0.6f + 0.8f * next() - 0.4f;
    }
    j.current.buffers[int(rtd::Buffer::Motion)] = {mx, my};
    rtd::reproject(j.current, &j.previous, {}, j.reprojection);
    return j;
  }();
  return in;
}

// Runs `body` once per iteration on CPU path state.range(0) in a one-thread arena.
template <class Body> void onPath(benchmark::State& state, Body&& body) {
  const int path = int(state.range(0));
  if (!rtd::cpuPathSupported(rtd::CpuPath(path))) {
    state.SkipWithError("this CPU lacks the path");
    return;
  }
  const rtd::CpuPath previous = rtd::setCpuPath(rtd::CpuPath(path));
  tbb::task_arena arena(1);
  for (auto _ : state) arena.execute(body);
  rtd::setCpuPath(previous);
  state.SetItemsProcessed(state.iterations() * int64_t(kW) * kH);
}

void BM_Reproject(benchmark::State& state) {
  const Inputs& in = inputs();
  rtd::Reprojection out;
  onPath(state, [&] {
    rtd::reproject(in.current, &in.previous, {}, out);
    benchmark::DoNotOptimize(&out);
  });
}
BENCHMARK(BM_Reproject)->DenseRange(0, 2)->ArgName("path")->Unit(benchmark::kMillisecond);

// BMFR's reprojection settings (position test of 4 footprints and normal test, no depth,
// no object id, no 3x3 fallback), on the scene's frames.
void BM_ReprojectBmfr(benchmark::State& state) {
  const Inputs& in = inputs();
  rtd::Reprojection out;
  const rtd::ReprojectionSettings s = rtd::BmfrSettings{}.reprojection;
  onPath(state, [&] {
    rtd::reproject(in.current, &in.previous, s, out);
    benchmark::DoNotOptimize(&out);
  });
}
BENCHMARK(BM_ReprojectBmfr)->DenseRange(1, 2)->ArgName("path")->Unit(benchmark::kMillisecond);

// The same passes on the jittered motion field (jitteredInputs).
void BM_ReprojectJittered(benchmark::State& state) {
  const Inputs& in = jitteredInputs();
  rtd::Reprojection out;
  onPath(state, [&] {
    rtd::reproject(in.current, &in.previous, {}, out);
    benchmark::DoNotOptimize(&out);
  });
}
BENCHMARK(BM_ReprojectJittered)->DenseRange(1, 2)->ArgName("path")->Unit(benchmark::kMillisecond);
void BM_TemporalAccumulationJittered(benchmark::State& state) {
  const Inputs& in = jitteredInputs();
  rtd::TemporalAccumulator acc;
  acc.resize(kW, kH);
  acc.run(in.reprojection, in.color, 0.2f, 0.2f, 32);
  onPath(state, [&] { acc.run(in.reprojection, in.color, 0.2f, 0.2f, 32); });
}
BENCHMARK(BM_TemporalAccumulationJittered)->DenseRange(1, 2)->ArgName("path")->Unit(benchmark::kMillisecond);

// Colour and both luminance moments (SVGF's accumulation, alpha 0.2 / 0.2). The history is
// carried from iteration to iteration, as from frame to frame.
void BM_TemporalAccumulation(benchmark::State& state) {
  const Inputs& in = inputs();
  rtd::TemporalAccumulator acc;
  acc.resize(kW, kH);
  acc.run(in.reprojection, in.color, 0.2f, 0.2f, 32);
  onPath(state, [&] { acc.run(in.reprojection, in.color, 0.2f, 0.2f, 32); });
}
BENCHMARK(BM_TemporalAccumulation)->DenseRange(0, 2)->ArgName("path")->Unit(benchmark::kMillisecond);

// TAA with the default settings (YCoCg box clamp, alpha 0.1, display domain) and the history
// filter of the second argument (0 bilinear, 1 catmullRom).
void BM_Taa(benchmark::State& state) {
  const Inputs& in = inputs();
  rtd::Taa taa;
  taa.resize(kW, kH);
  rtd::TaaSettings s;
  s.taaHistoryFilter = state.range(1) ? rtd::TaaHistoryFilter::catmullRom : rtd::TaaHistoryFilter::bilinear;
  taa.run(in.reprojection, in.color, s);
  onPath(state, [&] { benchmark::DoNotOptimize(taa.run(in.reprojection, in.color, s)[0].data.data()); });
}
BENCHMARK(BM_Taa)->ArgsProduct({{0, 1, 2}, {0, 1}})->ArgNames({"path", "catmullRom"})->Unit(benchmark::kMillisecond);

}  // namespace
