// Google Benchmark: supersampling with guide rays (Voorhuis Sec. 5, Fig. 15) at 1280x720: the
// assignment + Eq. 7 pre-mix and the post-filter copy per extra sample count. The filter itself
// runs at guide resolution, so this (and the extra paths) is all supersampling adds to it.
#include <benchmark/benchmark.h>

#include <random>

#include "rtd/guide_rays.h"

namespace {

constexpr int kW = 1280, kH = 720;

void BM_GuideRays(benchmark::State& state) {
  const int spp = int(state.range(0));
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f), z(1.0f, 4.0f);
  auto frame = [&]() {
    rtd::Frame f;
    f.width = kW;
    f.height = kH;
    for (rtd::Buffer b : {rtd::Buffer::Color, rtd::Buffer::Diffuse, rtd::Buffer::Specular, rtd::Buffer::Normal})
      f[b] = rtd::Image(kW, kH, 3, 0.5f);
    f[rtd::Buffer::Depth] = rtd::Image(kW, kH, 1);
    for (float& v : f[rtd::Buffer::Depth].pixels) v = z(rng);
    return f;
  };
  const rtd::Frame guides = frame();
  rtd::GuideRaySamples s;
  for (int k = 1; k < spp; ++k) {
    s.samples.push_back(frame());
    rtd::Image off(kW, kH, 2);
    for (float& v : off.pixels) v = u(rng);
    s.offsets.push_back(std::move(off));
  }
  rtd::GuideRays gr;
  for (auto _ : state) {
    const rtd::Frame mixed = gr.premix(guides, s);
    const rtd::Image out = gr.resolve(mixed[rtd::Buffer::Color]);
    benchmark::DoNotOptimize(out.pixels.data());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(kW) * kH);
}
BENCHMARK(BM_GuideRays)->Arg(2)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
