// Sequence I/O of `rtdenoise denoise` (issue 20 item 4): where the time of reading one frame and
// writing one output goes. The argument of each benchmark is the size of OpenEXR's thread pool
// (rtd::setExrThreads; 0 = the calling thread alone).
//
// Inputs: RTD_BENCH_NATIVE = a native sequence (e.g. `rtdenoise render --scene dynamic`, 28
// buffers), RTD_BENCH_BLENDER = a Blender multilayer sequence, RTD_BENCH_OUTPUT = an RGB EXR
// (e.g. a `denoise` output) to write again; frame 0 of each is used. Without them: a synthetic
// 320x180 native frame, the 64x36 Blender fixture, and the synthetic frame's colour.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdlib>
#include <map>

#include "io/exr.h"
#include "rtd/sequence.h"
#include "synthetic/synthetic.h"

namespace {

namespace fs = std::filesystem;
using namespace rtd;

fs::path scratch() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("rtd_io_bench_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

fs::path nativeSequence() {
  if (const char* d = std::getenv("RTD_BENCH_NATIVE")) return d;
  static const fs::path dir = [] {
    synthetic::Scene scene;
    scene.width = 320;
    scene.height = 180;
    SequenceWriter w(scratch() / "native");
    w.write(synthetic::makeFrame(scene, 0));
    w.finish();
    return w.dir();
  }();
  return dir;
}

fs::path blenderSequence() {
  if (const char* d = std::getenv("RTD_BENCH_BLENDER")) return d;
  return fs::path(RTD_SOURCE_DIR) / "tests/fixtures/blender";
}

fs::path sequence(int64_t which) { return which == 0 ? nativeSequence() : blenderSequence(); }

// Arguments: {sequence (0 native, 1 Blender), OpenEXR threads}.
void sequenceArgs(benchmark::internal::Benchmark* b) {
  for (int which : {0, 1})
    for (int threads : {0, 1, 2}) b->Args({which, threads});
  b->ArgNames({"blender", "exrThreads"})->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
}

// Channels of the first frame grouped by layer (everything before the last '.'), as the
// readers asked for them before: one readChannels call per buffer.
std::vector<std::vector<std::string>> channelGroups(const fs::path& file) {
  std::map<std::string, std::vector<std::string>> groups;
  for (const auto& c : exr::readHeader(file).channels) groups[c.substr(0, c.rfind('.'))].push_back(c);
  std::vector<std::vector<std::string>> out;
  for (auto& [layer, names] : groups) out.push_back(names);
  return out;
}

// What SequenceReader::read costs: header check, decoding, the interleaving copy.
void BM_ReadFrame(benchmark::State& st) {
  setExrThreads(int(st.range(1)));
  const auto reader = SequenceReader::open(sequence(st.range(0)));
  for (auto _ : st) benchmark::DoNotOptimize(reader->read(0));
  setExrThreads(0);
}
BENCHMARK(BM_ReadFrame)->Apply(sequenceArgs);

// Every channel of the file in one readChannels call (one decoding pass): the floor of a read.
void BM_ReadAllChannelsOnce(benchmark::State& st) {
  setExrThreads(int(st.range(1)));
  const fs::path file = SequenceReader::open(sequence(st.range(0)))->framePath(0);
  std::vector<std::string> names;
  for (const auto& g : channelGroups(file)) names.insert(names.end(), g.begin(), g.end());
  for (auto _ : st) benchmark::DoNotOptimize(exr::readChannels(file, names, ""));
  st.counters["channels"] = double(names.size());
  setExrThreads(0);
}
BENCHMARK(BM_ReadAllChannelsOnce)->Apply(sequenceArgs);

// The readers' old pattern: one call (one decoding of the whole file) per buffer.
void BM_ReadChannelsPerBuffer(benchmark::State& st) {
  setExrThreads(int(st.range(1)));
  const fs::path file = SequenceReader::open(sequence(st.range(0)))->framePath(0);
  const auto groups = channelGroups(file);
  for (auto _ : st)
    for (const auto& g : groups) benchmark::DoNotOptimize(exr::readChannels(file, g, ""));
  st.counters["calls"] = double(groups.size());
  setExrThreads(0);
}
BENCHMARK(BM_ReadChannelsPerBuffer)->Apply(sequenceArgs);

void BM_ReadHeader(benchmark::State& st) {
  const fs::path file = SequenceReader::open(sequence(st.range(0)))->framePath(0);
  for (auto _ : st) benchmark::DoNotOptimize(exr::readHeader(file));
}
BENCHMARK(BM_ReadHeader)->Arg(0)->Arg(1)->ArgName("blender")->Unit(benchmark::kMillisecond);

Image outputImage() {
  if (const char* f = std::getenv("RTD_BENCH_OUTPUT")) return readRgbExr(f);
  return SequenceReader::open(nativeSequence())->read(0)[Buffer::Color];
}

// One denoised frame as `denoise` writes it (ZIP, temporary file + rename): float or half.
void BM_WriteOutput(benchmark::State& st) {
  setExrThreads(int(st.range(1)));
  const Image rgb = outputImage();
  const fs::path out = scratch() / "out.exr";
  for (auto _ : st) writeRgbExr(out, rgb, st.range(0) ? ExrPixels::Half : ExrPixels::Float);
  st.counters["bytes"] = double(fs::file_size(out));
  setExrThreads(0);
}
BENCHMARK(BM_WriteOutput)
    ->ArgsProduct({{0, 1}, {0, 1, 2}})
    ->ArgNames({"half", "exrThreads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

// The same output with OpenEXR alone (no temporary file), single-threaded, by compression:
// 0 none, 2 ZIPS, 3 ZIP (OpenEXR's default zlib level), 4 PIZ (Imf::Compression numbering).
void BM_WriteCompression(benchmark::State& st) {
  const Image rgb = outputImage();
  const fs::path out = scratch() / "raw.exr";
  Imf::Header header(rgb.width, rgb.height);
  header.compression() = Imf::Compression(st.range(0));
  Imf::FrameBuffer fb;
  const size_t xs = sizeof(float) * size_t(rgb.channels), ys = xs * size_t(rgb.width);
  const char* names[] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
    fb.insert(names[c], Imf::Slice(Imf::FLOAT, (char*)(rgb.pixels.data() + c), xs, ys));
  }
  for (auto _ : st) {
    Imf::OutputFile file(out.c_str(), header, 0);
    file.setFrameBuffer(fb);
    file.writePixels(rgb.height);
  }
  st.counters["bytes"] = double(fs::file_size(out));
}
BENCHMARK(BM_WriteCompression)
    ->DenseRange(0, 4)
    ->ArgName("compression")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

}  // namespace
