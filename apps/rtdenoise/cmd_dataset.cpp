// rtdenoise dataset: renders the training/test data set of the learned methods (docs/dataset.md):
// procedural, built-in and glTF/JSON scenes as native sequences (1-spp input with every feature
// buffer, pixel centres, no jitter) with converged references (two or more independent
// reference batches, checked N/2 against N spp), plus a compact training cache per sequence
// (cache.npy / cameras.npy) written from what rtd's own SequenceReader reads back.
#ifdef HAVE_RTDENOISE_RENDER
#include <Imath/half.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli.h"
#include "rtd/render/procedural.h"
#include "rtd/render/render.h"

namespace rtd::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct DatasetOptions {
  std::string output;
  int seed = 1;
  int procedural = 20;
  std::string builtin = "cornell,pillars,glossy,dynamic";
  std::vector<std::string> scenes;
  std::string test = "glossy,dynamic";
  int testEvery = 5;
  int frames = 8;
  int testFrames = 0;
  std::string size = "256x256";
  int referenceSpp = 256;
  int maxReferenceSpp = 1024;
  double tolerance = 0.01;
  double fireflyFraction = 0.001;
  int threads = 0;
  std::string cacheDir;
  bool noCache = false;
  bool listOnly = false;
};

/// The training cache's channels, in order (docs/dataset.md): buffer and channel count.
const std::pair<Buffer, int> kCacheBuffers[] = {{Buffer::Color, 3},  {Buffer::Albedo, 3}, {Buffer::Normal, 3},
                                                {Buffer::Depth, 1},  {Buffer::Motion, 2}, {Buffer::Emission, 3}};
constexpr int kCacheChannels = 3 + 3 + 3 + 1 + 2 + 3 + 3;  // + reference RGB

struct SceneEntry {
  std::string name;         ///< directory name
  std::string scene;        ///< the built-in name, "procedural:<seed>" or the file
  std::string description;  ///< JSON text of a built-in or procedural scene; empty for a file
  bool test = false;
};

std::vector<SceneEntry> sceneList(const DatasetOptions& o, int width, int height) {
  std::vector<SceneEntry> list;
  const auto test = splitList(o.test);
  const std::set<std::string> held(test.begin(), test.end());
  const auto builtins = render::Scene::builtinScenes();
  for (const auto& b : splitList(o.builtin)) {
    if (std::find(builtins.begin(), builtins.end(), b) == builtins.end())
      throw UsageError("--builtin: '" + b + "' is not a built-in scene");
    list.push_back({b, b, render::Scene::builtinDescription(b), held.count(b) > 0});
  }
  for (int i = 0; i < o.procedural; ++i) {
    const uint32_t seed = uint32_t(o.seed) * 1000u + uint32_t(i);
    const std::string name = "procedural_" + std::to_string(seed);
    const bool test = held.count(name) > 0 || (o.testEvery > 0 && i % o.testEvery == o.testEvery - 1);
    const int frames = test && o.testFrames > 0 ? o.testFrames : o.frames;
    list.push_back({name, render::kProceduralPrefix + std::to_string(seed), render::proceduralSceneJson(seed, {frames, width, height}),
                    test});
  }
  for (const auto& f : o.scenes) {
    const std::string stem = fs::path(f).stem().string();
    list.push_back({stem, f, "", held.count(stem) > 0});
  }
  // Training scenes first: a partial data set (the index is rewritten after every sequence) can
  // already be trained on while the test scenes render.
  std::stable_partition(list.begin(), list.end(), [](const SceneEntry& e) { return !e.test; });
  std::set<std::string> names;
  for (const auto& e : list)
    if (!names.insert(e.name).second) throw Error("dataset: two scenes named '" + e.name + "'");
  return list;
}

/// x / (1 + x): the tone curve of the convergence check (every value in [0, 1)).
float tone(float x) { return x / (1.0f + x); }
float lum(const float* c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

/// Convergence of a reference R (N spp) from its first half A (N/2 spp) and second half B:
/// RMSE of tone(A) - tone(R) over pixels and channels, and fireflies: pixels whose luminance
/// spikes above 3x the median of their 8 neighbours + 0.1 while the halves disagree by more
/// than half of it (a spike of one batch, not a small highlight both see).
struct Convergence {
  double rmse = 0;
  int fireflies = 0;
  bool passed(const DatasetOptions& o, int pixels) const {
    return rmse <= o.tolerance && fireflies <= int(o.fireflyFraction * pixels);
  }
};

Convergence convergence(const Image& a, const Image& b, const Image& r) {
  Convergence c;
  double sum = 0;
  for (size_t i = 0; i < r.pixels.size(); ++i) {
    const double d = tone(a.pixels[i]) - tone(r.pixels[i]);
    sum += d * d;
  }
  c.rmse = std::sqrt(sum / double(std::max<size_t>(1, r.pixels.size())));
  for (int y = 1; y + 1 < r.height; ++y)
    for (int x = 1; x + 1 < r.width; ++x) {
      float n[8];
      int k = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (dx || dy) n[k++] = lum(r.pixel(x + dx, y + dy));
      std::nth_element(n, n + 4, n + 8);
      const float l = lum(r.pixel(x, y));
      if (l > 3.0f * n[4] + 0.1f && std::fabs(lum(a.pixel(x, y)) - lum(b.pixel(x, y))) > 0.5f * l) ++c.fireflies;
    }
  return c;
}

/// Writes a NumPy .npy file (format 1.0, little-endian, C order) atomically.
void writeNpy(const fs::path& path, const std::string& descr, const std::vector<size_t>& shape, const void* data, size_t bytes) {
  std::string dims;
  for (size_t d : shape) dims += (dims.empty() ? "" : ", ") + std::to_string(d);
  if (shape.size() == 1) dims += ",";
  std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (" + dims + "), }";
  header.append((64 - (10 + header.size() + 1) % 64) % 64, ' ');  // data starts 64-byte aligned
  header += '\n';
  std::string out = "\x93NUMPY";
  for (const size_t byte : {size_t(1), size_t(0), header.size() & 0xFF, header.size() >> 8}) out.push_back(char(byte));
  out += header;
  out.append(static_cast<const char*>(data), bytes);
  writeFileAtomic(path, out);
}

/// Writes cache.npy (float16 [frames, 18, H, W]) and cameras.npy (float32 [frames, 2, 4, 4]) of
/// the sequence in `dir` and its reference `dir/reference`, both read with SequenceReader.
/// Returns the number of values clamped to the float16 range.
uint64_t writeTrainingCache(const fs::path& dir) {
  auto seq = SequenceReader::open(dir);
  auto ref = SequenceReader::open(dir / "reference");
  if (ref->frameCount() != seq->frameCount())
    throw Error("sequence '" + dir.string() + "': " + std::to_string(seq->frameCount()) + " frames but " +
                std::to_string(ref->frameCount()) + " references");
  const int n = seq->frameCount(), w = seq->width(), h = seq->height();
  const size_t plane = size_t(w) * h;
  std::vector<Imath::half> cache(size_t(n) * kCacheChannels * plane);
  std::vector<float> cameras(size_t(n) * 32);
  uint64_t clamped = 0;
  constexpr float kHalfMax = 65504.0f;
  for (int i = 0; i < n; ++i) {
    const Frame f = seq->read(i), r = ref->read(i);
    int channel = 0;
    auto put = [&](const Image& img, int channels, const std::string& what) {
      if (img.empty() || img.channels < channels || img.width != w || img.height != h)
        throw Error("sequence '" + dir.string() + "', frame " + std::to_string(f.number) + ": buffer '" + what + "' missing or wrong size");
      for (int c = 0; c < channels; ++c, ++channel) {
        Imath::half* dst = cache.data() + (size_t(i) * kCacheChannels + channel) * plane;
        for (size_t p = 0; p < plane; ++p) {
          float v = img.pixels[p * img.channels + c];
          if (!std::isfinite(v)) v = 0;
          if (std::fabs(v) > kHalfMax) {
            v = std::copysign(kHalfMax, v);
            ++clamped;
          }
          dst[p] = Imath::half(v);
        }
      }
    };
    for (const auto& [b, c] : kCacheBuffers) put(f[b], c, std::string(bufferName(b)));
    put(r[Buffer::Color], 3, "reference color");
    std::copy(f.camera.worldToCamera.begin(), f.camera.worldToCamera.end(), cameras.begin() + size_t(i) * 32);
    std::copy(f.camera.projection.begin(), f.camera.projection.end(), cameras.begin() + size_t(i) * 32 + 16);
  }
  static_assert(sizeof(Imath::half) == 2);
  writeNpy(dir / "cache.npy", "<f2", {size_t(n), size_t(kCacheChannels), size_t(h), size_t(w)}, cache.data(), cache.size() * 2);
  writeNpy(dir / "cameras.npy", "<f4", {size_t(n), 2, 4, 4}, cameras.data(), cameras.size() * 4);
  return clamped;
}

json cacheLayout() {
  json channels = json::array();
  for (const auto& [b, c] : kCacheBuffers)
    for (int k = 0; k < c; ++k) channels.push_back(std::string(bufferName(b)) + "." + std::string(1, bufferChannels(b)[k]));
  for (const char* c : {"reference.R", "reference.G", "reference.B"}) channels.push_back(c);
  return {{"file", "cache.npy"},
          {"dtype", "float16"},
          {"shape", "[frames, channels, height, width]"},
          {"channels", channels},
          {"cameras", {{"file", "cameras.npy"}, {"dtype", "float32"}, {"shape", "[frames, 2, 4, 4]"},
                       {"content", "worldToCamera then projection, row-major (rtd::Camera)"}}},
          {"conventions", "buffers exactly as rtd::Frame (include/rtd/frame.h): linear radiance including emission, "
                          "world-space normals, linear view depth, motion in pixels; values beyond the float16 range clamped"}};
}

void runDataset(const DatasetOptions& o) {
  if (o.output.empty() && !o.listOnly) throw UsageError("--output is required (unless --list)");
  if (o.frames < 1) throw UsageError("--frames: must be >= 1");
  if (o.testFrames < 0) throw UsageError("--test-frames: must be >= 0");
  if (o.referenceSpp < 2 || o.referenceSpp % 2) throw UsageError("--reference-spp: must be an even number >= 2");
  if (o.maxReferenceSpp < o.referenceSpp) throw UsageError("--max-reference-spp: must be >= --reference-spp");
  if (o.tolerance <= 0) throw UsageError("--tolerance: must be > 0");
  // Not a structured binding: clang 14 (the asan preset) cannot capture one in the lambdas below.
  const std::pair<int, int> size = parseSize(o.size);
  const int width = size.first, height = size.second;
  const std::vector<SceneEntry> scenes = sceneList(o, width, height);
  if (o.listOnly) {
    for (const auto& e : scenes) std::printf("%-5s %-24s %s\n", e.test ? "test" : "train", e.name.c_str(), e.scene.c_str());
    return;
  }
  std::unique_ptr<tbb::global_control> threads;
  if (o.threads > 0) threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(o.threads));
  render::ReferenceCache cache;
  if (!o.noCache) cache.dir = o.cacheDir.empty() ? render::ReferenceCache::defaultDir() : fs::path(o.cacheDir);

  const fs::path out(o.output);
  fs::create_directories(out);
  // Steps: per frame one input and two reference batches (more when the check asks for them).
  int steps = 0;
  for (const auto& e : scenes) steps += 3 * (e.test && o.testFrames > 0 ? o.testFrames : o.frames);
  Progress progress("dataset", steps);
  int done = 0;
  json sequences = json::array();
  const auto start = std::chrono::steady_clock::now();
  // dataset.json, rewritten after every sequence ("complete": false until the last).
  auto writeIndex = [&](bool complete) {
    json index = {{"generator", "rtdenoise dataset"},
                  {"version", 1},
                  {"complete", complete},
                  {"seed", o.seed},
                  {"size", {width, height}},
                  {"frames", o.frames},
                  {"testFrames", o.testFrames > 0 ? o.testFrames : o.frames},
                  {"spp", 1},
                  {"pixelJitter", false},
                  {"reference", {{"spp", o.referenceSpp}, {"maxSpp", o.maxReferenceSpp}, {"tolerance", o.tolerance},
                                 {"fireflyFraction", o.fireflyFraction},
                                 {"check", "RMSE of x/(1+x) between the N/2-spp half and the N-spp reference <= tolerance, "
                                           "and at most fireflyFraction x pixels fireflies; else the spp doubles up to maxSpp"}}},
                  {"cache", cacheLayout()},
                  {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()},
                  {"sequences", sequences}};
    writeFileAtomic(out / "dataset.json", index.dump(1) + "\n");
  };
  for (const SceneEntry& e : scenes) {
    const auto sceneStart = std::chrono::steady_clock::now();
    auto scene = e.description.empty() ? render::Scene::load(e.scene) : render::Scene::fromJson(e.description, fs::current_path(), e.scene);
    render::RenderSettings s = scene->suggestedSettings();
    s.width = width;
    s.height = height;
    s.spp = 1;
    s.pixelJitter = false;  // pixel-perfect: features, input and reference through the pixel centre
    s.seed = uint32_t(o.seed);
    s.allBuffers = true;
    const int frames = std::min(e.test && o.testFrames > 0 ? o.testFrames : o.frames, scene->frameCount());
    render::Renderer renderer(scene, s);
    // Independent reference batches of N/2 spp: batch k renders with its own seed.
    std::vector<std::unique_ptr<render::Renderer>> batches;
    auto batch = [&](int k) -> render::Renderer& {
      while (int(batches.size()) <= k) {
        render::RenderSettings bs = s;
        bs.seed = uint32_t(o.seed) + 7919u * uint32_t(batches.size() + 1);
        batches.push_back(std::make_unique<render::Renderer>(scene, bs));
      }
      return *batches[k];
    };
    const fs::path dir = out / (e.test ? "test" : "train") / e.name;
    fs::create_directories(dir / "reference");
    SequenceWriter writer(dir), refWriter(dir / "reference");
    json frameInfo = json::array();
    const int half = o.referenceSpp / 2;
    for (int i = 0; i < frames; ++i) {
      Frame f = renderer.render(i);
      writer.write(f);
      progress.update(++done, e.name + " frame " + std::to_string(i + 1));
      // Batches until converged: A = mean of the first half of the batches, R = mean of all.
      std::vector<Image> images;
      Convergence conv;
      Image mean;
      for (int k = 0;; ++k) {
        images.push_back(cache.fetchOrRender(batch(k), *scene, i, half, 0, render::Eye::Center));
        if (k == 0 || (k + 1) & k) continue;  // evaluate at 2, 4, 8, ... batches
        const int m = int(images.size());
        Image a(width, height, 3), b(width, height, 3);
        mean = Image(width, height, 3);
        for (int j = 0; j < m; ++j)
          for (size_t p = 0; p < mean.pixels.size(); ++p) (j < m / 2 ? a : b).pixels[p] += images[j].pixels[p] / float(m / 2);
        for (size_t p = 0; p < mean.pixels.size(); ++p) mean.pixels[p] = 0.5f * (a.pixels[p] + b.pixels[p]);
        conv = convergence(a, b, mean);
        progress.update(done += (k == 1 ? 2 : 0), e.name + " reference " + std::to_string(i + 1) + " (" + std::to_string(m * half) + " spp)");
        if (conv.passed(o, width * height) || 2 * m * half > o.maxReferenceSpp) break;
      }
      const int spp = int(images.size()) * half;
      Frame ref;
      ref.number = f.number;
      ref.width = f.width;
      ref.height = f.height;
      ref.camera = f.camera;
      ref[Buffer::Color] = std::move(mean);
      refWriter.write(ref);
      frameInfo.push_back({{"frame", f.number}, {"referenceSpp", spp}, {"rmseHalf", conv.rmse}, {"fireflies", conv.fireflies},
                           {"converged", conv.passed(o, width * height)}});
    }
    writer.finish();
    refWriter.finish();
    const uint64_t clamped = writeTrainingCache(dir);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sceneStart).count();
    json seqInfo = {{"name", e.name},         {"scene", e.scene}, {"split", e.test ? "test" : "train"},
                    {"dir", fs::relative(dir, out).generic_string()}, {"frames", frames}, {"seconds", seconds},
                    {"float16Clamped", clamped}, {"frameInfo", frameInfo}};
    // The description rendered, so `rtdenoise render --scene <dir>/scene.json` renders it again.
    if (!e.description.empty()) writeFileAtomic(dir / "scene.json", e.description + "\n");
    sequences.push_back(seqInfo);
    writeIndex(false);
  }
  progress.finish();
  writeIndex(true);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  int unconverged = 0;
  for (const auto& sq : sequences)
    for (const auto& f : sq["frameInfo"]) unconverged += !f["converged"].get<bool>();
  std::printf("dataset: %zu sequence(s) at %dx%d, %.1f s -> %s%s\n", sequences.size(), width, height, seconds,
              out.string().c_str(),
              unconverged ? (" (" + std::to_string(unconverged) + " reference(s) not converged, flagged in dataset.json)").c_str() : "");
}

}  // namespace

void addDataset(CLI::App& app) {
  auto o = std::make_shared<DatasetOptions>();
  auto* cmd = addSubcommand(app, "dataset", "render the learned methods' training/test data set (docs/dataset.md)");
  cmd->add_option("--output,-o", o->output, "REQUIRED (unless --list): output directory (dataset.json, train/<scene>/, test/<scene>/)");
  cmd->add_option("--seed", o->seed, "seed of the procedural scenes and of every render")->default_val(1);
  cmd->add_option("--procedural", o->procedural, "number of procedural scenes (seeds 1000*seed + i)")->default_val(20);
  cmd->add_option("--builtin", o->builtin, "comma-separated built-in scenes to include")->default_val(o->builtin);
  cmd->add_option("--scene", o->scenes, "a .gltf/.glb/.json scene to include (repeatable)");
  cmd->add_option("--test", o->test, "comma-separated scene names held out as the test split")->default_val(o->test);
  cmd->add_option("--test-every", o->testEvery, "hold out every k-th procedural scene as test (0: none)")->default_val(5);
  cmd->add_option("--frames", o->frames, "frames per sequence (consecutive, from the first)")->default_val(8);
  cmd->add_option("--test-frames", o->testFrames, "frames per test sequence (0: as --frames)")->default_val(0);
  cmd->add_option("--size", o->size, "WxH of every frame")->default_val(o->size);
  cmd->add_option("--reference-spp", o->referenceSpp, "reference samples per pixel N (two batches of N/2)")->default_val(256);
  cmd->add_option("--max-reference-spp", o->maxReferenceSpp, "the check may double the spp up to this")->default_val(1024);
  cmd->add_option("--tolerance", o->tolerance, "convergence: RMSE of x/(1+x), N/2 vs N spp")->default_val(0.01);
  cmd->add_option("--firefly-fraction", o->fireflyFraction, "convergence: most fireflies allowed, as a fraction of the pixels")
      ->default_val(0.001);
  cmd->add_option("--threads", o->threads, "CPU threads (0 = all cores)")->capture_default_str()->check(atLeast(0));
  cmd->add_option("--reference-cache", o->cacheDir, "reference cache directory (default as `render`)");
  cmd->add_flag("--no-reference-cache", o->noCache, "do not read or write the reference cache");
  cmd->add_flag("--list", o->listOnly, "print the scene list with its split and exit");
  cmd->callback([o] { runDataset(*o); });
}

}  // namespace rtd::cli

#endif  // HAVE_RTDENOISE_RENDER
