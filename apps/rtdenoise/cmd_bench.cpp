// rtdenoise bench: per-pass timings of one method on the analytic synthetic scene.
#include <algorithm>
#include <ctime>
#include <map>
#include <nlohmann/json.hpp>
#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#endif

#include "cli.h"
#include "core/cpu_path.h"
#include "synthetic/synthetic.h"

namespace rtd::cli {

namespace {
struct BenchOptions {
  std::string method = "svgf";
  std::string size = "1280x720";
  DeviceOptions device;
  std::vector<std::string> settings;
  int frames = 20;
  int warmup = 5;
  std::string json;
  bool sampleMask = false;
  bool ftzDaz = false;
  bool stereo = false;
  std::string input;  // a sequence to time instead of the synthetic scene
  int inputFrames = 0;  // 0: all of the sequence
};

// CPU time of the whole process (all threads), milliseconds.
double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// --ftz-daz: flush-to-zero and denormals-are-zero in this benchmark process's MXCSR, set
// before the device's thread arena starts (oneTBB workers take the floating-point settings of
// the thread that initializes the arena). Only to compare: the library never sets them, and
// the figures it is measured by are without.
void setFlushToZero() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_setcsr(_mm_getcsr() | 0x8040);  // FTZ (bit 15) | DAZ (bit 6)
#else
  throw Error("--ftz-daz is only implemented on x86");
#endif
}

// `f` copied into `into`'s buffers (allocated on the first call): the frame to denoise, in the
// same memory every frame, just written, as an application hands over the buffers its renderer
// has just filled. (Each frame in memory of its own, read once, cost the import ~1.5x on the
// first read of each page.)
void refill(const Frame& f, Frame& into) {
  if (into.width != f.width || into.height != f.height) into = Frame{};
  for (size_t b = 0; b < f.buffers.size(); ++b) {
    if (into.buffers[b].pixels.size() != f.buffers[b].pixels.size()) into.buffers[b] = f.buffers[b];
    else into.buffers[b].pixels = f.buffers[b].pixels;  // the same size: no reallocation
  }
  into.width = f.width;
  into.height = f.height;
  into.number = f.number;
  into.camera = f.camera;
  into.cut = f.cut;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void runBench(const BenchOptions& o) {
  auto [w, h] = parseSize(o.size);
  (void)methodInfo(o.method);
  if (o.ftzDaz) setFlushToZero();
  auto device = Device::create(o.device.desc(o.device.single()));
  // --stereo: both eyes through the two-view denoiser (rtd/stereo.h); timings summed over the eyes.
  std::unique_ptr<Denoiser> denoiser;
  std::unique_ptr<StereoDenoiser> stereo;
  if (o.stereo) {
    stereo = device->createStereoDenoiser(o.method);
    applySettings(*stereo, o.settings);
  } else {
    denoiser = device->createDenoiser(o.method);
    applySettings(*denoiser, o.settings);
  }

  // Frames of a camera moving forward, each one step after the last, so that every frame's
  // motion vectors point into the frame before it and reprojection does its real work: the
  // synthetic scene's frame i, or frame i of a sequence (--input; cycled over its first
  // --input-frames). At a cycle's wrap the camera jumps back: the history is reset there as at
  // a camera cut, and that frame (which has no history) is not timed. (Played backwards
  // instead, a sequence's motion vectors would point the wrong way and reprojection would fail
  // on most pixels.)
  std::unique_ptr<SequenceReader> seq;
  int cycle = 0;  // frames of the sequence used
  synthetic::Scene scene;
  if (!o.input.empty()) {
    seq = SequenceReader::open(o.input);
    cycle = o.inputFrames > 0 ? std::min(o.inputFrames, seq->frameCount()) : seq->frameCount();
    if (cycle < 2) throw Error("bench: input '" + o.input + "' has fewer than two frames");
    w = seq->width();
    h = seq->height();
  } else {
    scene.width = w;
    scene.height = h;
  }
  // The right eye (--stereo, synthetic scene only): the same view with its own noise (the
  // synthetic scene has one camera; every pixel then reprojects into the other eye, the
  // exchange's most work).
  synthetic::Scene right = scene;
  right.seed = scene.seed + 1;
  auto make = [&](int k, bool rightEye) { return seq ? seq->read(k) : synthetic::makeFrame(rightEye ? right : scene, k); };
  // The path's frames are made or read before timing while they fit kPreloadBytes, and each is
  // copied into the same buffers (refill) right before its denoise call. Beyond the budget each
  // frame is made or read when it is needed: that work between the calls also leaves the
  // denoiser's planes out of the caches (Dundr at 1280x720: ~1.5 ms more), and the output says
  // so.
  constexpr uint64_t kPreloadBytes = uint64_t(3) << 30;
  // The frames the run shows: a sequence longer than the run is not cycled, only its first
  // warm-up + timed frames are read.
  const int distinct = seq ? std::min(cycle, o.warmup + o.frames) : o.warmup + o.frames;
  std::vector<Frame> preloaded, preloadedRight;
  bool preload = true;
  for (int k = 0; k < distinct && preload; ++k) {
    preloaded.push_back(make(k, false));
    if (stereo) preloadedRight.push_back(make(k, true));
    if (k == 0) {
      uint64_t bytes = 0;
      for (const Image& b : preloaded[0].buffers) bytes += b.pixels.size() * sizeof(float);
      preload = bytes * (stereo ? 2 : 1) * uint64_t(distinct) <= kPreloadBytes;
    }
  }
  if (!preload) preloaded.clear(), preloadedRight.clear();
  Frame current, currentRight;
  Image output(w, h, 3), rightOutput(o.stereo ? w : 0, o.stereo ? h : 0, 3);
  // --sample-mask: a quarter of the pixels per frame (position in a 2x2 block, rotating over four
  // frames) as the frames' sampleMask, to time a progressive mode (svgf's useSampleMask). Only
  // the mask changes: the colour is left dense, which costs the same.
  std::vector<Image> masks;
  if (o.sampleMask)
    for (int phase = 0; phase < 4; ++phase) {
      Image m(w, h, 1);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) m.at(x, y) = ((x & 1) + 2 * (y & 1)) == phase ? 1.0f : 0.0f;
      masks.push_back(std::move(m));
    }

  std::map<std::string, std::vector<double>> passes, passesCpu;
  std::vector<std::string> order;
  std::vector<double> totals, cpuTimes;
  Progress progress("bench " + o.method, o.warmup + o.frames);
  for (int i = 0, timed = 0; timed < o.frames; ++i) {
    const bool cut = seq && i > 0 && i % cycle == 0;
    if (cut) denoiser->reset();  // --input: not with --stereo
    const int k = seq ? i % cycle : i;  // the frame of the path
    refill(preload ? preloaded[size_t(k)] : make(k, false), current);
    if (stereo) refill(preload ? preloadedRight[size_t(k)] : make(k, true), currentRight);
    FrameInputs in = current.inputs();
    if (o.sampleMask) in[Buffer::SampleMask] = masks[size_t(i % 4)].view();
    const double cpuStart = processCpuMs();
    if (stereo) {
      StereoFrameInputs pair;
      pair.eye[0] = in;
      pair.eye[1] = currentRight.inputs();
      if (o.sampleMask) pair.eye[1][Buffer::SampleMask] = masks[size_t((i + 2) % 4)].view();
      stereo->denoise(pair, output.view(), rightOutput.view());
    } else {
      denoiser->denoise(in, output.view());
    }
    const double cpu = processCpuMs() - cpuStart;
    const FrameStats& st = stereo ? stereo->stats() : denoiser->stats();
    if (i < o.warmup) progress.update(i + 1);
    if (i < o.warmup || cut) continue;
    progress.update(o.warmup + ++timed);
    for (const auto& p : st.passes) {
      if (!passes.count(p.name)) order.push_back(p.name);
      passes[p.name].push_back(p.milliseconds);
      passesCpu[p.name].push_back(p.cpuMilliseconds);
    }
    totals.push_back(st.totalMilliseconds);
    cpuTimes.push_back(cpu);
  }
  progress.finish();
  const FrameStats& last = stereo ? stereo->stats() : denoiser->stats();

  std::printf("method %s, %s%dx%d, %s, %d frames after %d warm-up (medians)%s%s%s%s%s\n", o.method.c_str(),
              o.stereo ? "both eyes of " : "", w, h, device->name().c_str(), o.frames, o.warmup,
              o.sampleMask ? ", 1/4 sample mask" : "", o.ftzDaz ? ", FTZ/DAZ set in this process" : "",
              o.input.empty() ? "" : ", input ", o.input.c_str(),
              preload ? "" : ", each frame made or read between the timed calls (caches cold)");
  nlohmann::json j = {{"method", o.method}, {"width", w}, {"height", h}, {"device", device->name()},
                      {"backend", std::string(backendName(device->backend()))}, {"frames", o.frames},
                      {"sampleMask", o.sampleMask}, {"ftzDaz", o.ftzDaz}, {"stereo", o.stereo},
                      {"framesPreloaded", preload}};
  if (!o.input.empty()) j["input"] = o.input;
  if (device->backend() == Backend::Cpu) {
    // The SIMD path the CPU passes dispatched to (RTD_CPU_PATH forces one).
    std::printf("  cpu path: %s\n", describeCpuPath().c_str());
    j["cpuPath"] = cpuPathName(cpuPath());
  }
  // Per pass: the wall time, and on the CPU backend the process CPU time during the pass (all
  // threads; with --threads 1 the pass's own cost, which other work on the machine barely moves).
  const bool cpuColumn = device->backend() == Backend::Cpu;
  if (cpuColumn) std::printf("  %-24s %9s    %9s\n", "pass", "wall", "cpu");
  for (const auto& name : order) {
    const double m = median(passes[name]);
    if (cpuColumn) {
      const double c = median(passesCpu[name]);
      std::printf("  %-24s %9.3f ms %9.3f ms\n", name.c_str(), m, c);
      j["passesCpuMedianMs"][name] = c;
    } else {
      std::printf("  %-24s %9.3f ms\n", name.c_str(), m);
    }
    j["passesMedianMs"][name] = m;
  }
  const double total = median(totals);
  std::printf("  %-24s %9.3f ms\n", "total", total);
  j["totalMedianMs"] = total;
  // Process CPU time per frame (every thread): less sensitive than wall time to other
  // processes sharing the cores; / threads is the wall time of a perfectly parallel frame.
  const double cpu = median(cpuTimes);
  std::printf("  %-24s %9.3f ms\n", "cpu time (all threads)", cpu);
  j["cpuMedianMs"] = cpu;
  for (const auto& m : last.memory) {  // FrameStats::memory: every method, both backends
    std::printf("  memory %-17s %9.2f MiB\n", m.category.c_str(), double(m.bytes) / (1 << 20));
    j["memoryBytes"][m.category] = m.bytes;
  }
  if (!o.json.empty()) writeFileAtomic(o.json, j.dump(1));
}
}  // namespace

void addBench(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  auto* cmd = addSubcommand(app, "bench", "time a method's passes on a synthetic scene or a sequence (medians)");
  cmd->add_option("--method,-m", o->method, "method name (see `rtdenoise methods`)")->capture_default_str();
  cmd->add_option("--size", o->size, "WIDTHxHEIGHT")->capture_default_str();
  o->device.add(cmd);
  cmd->add_option("--set,-s", o->settings, "setting as key=value (repeatable; presets such as variant= apply first)");
  cmd->add_option("--frames", o->frames, "timed frames (>= 1)")->capture_default_str()->check(atLeast(1));
  cmd->add_option("--warmup", o->warmup, "untimed frames first")->capture_default_str()->check(atLeast(0));
  cmd->add_option("--json", o->json, "FILE: also write the medians as JSON to FILE");
  cmd->add_flag("--sample-mask", o->sampleMask, "frames carry a rotating 1/4 sampleMask (progressive modes)");
  auto* input = cmd->add_option("--input,-i", o->input,
                                "time on the first frames of this sequence (e.g. a rendered mirrorfloor) instead of the "
                                "synthetic scene; --size is then the sequence's");
  cmd->add_option("--input-frames", o->inputFrames,
                  "with --input: the first N frames of the sequence, cycled forward (the wrap is a camera cut, not "
                  "timed; 0 = all)")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& v) { return v == "0" || std::atoi(v.c_str()) >= 2 ? std::string() : "must be 0 or at least 2"; },
          "0 or >= 2"))
      ->needs(input);
  cmd->add_flag("--stereo", o->stereo, "both eyes through the two-view denoiser (the right eye: other noise)")
      ->excludes(input);
  cmd->add_flag("--ftz-daz", o->ftzDaz,
                "set flush-to-zero and denormals-are-zero in this process first (for comparison only; "
                "the library never changes the caller's floating-point mode)");
  cmd->callback([o] { runBench(*o); });
}

}  // namespace rtd::cli
