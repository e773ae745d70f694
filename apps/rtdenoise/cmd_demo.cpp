// rtdenoise demo: the README's main job. Makes the built-in animated scene, runs every
// implemented method on it, evaluates them against the reference and writes the HTML report.
#ifdef HAVE_RTDENOISE_EVAL
#include <filesystem>

#include "cli.h"
#include "eval_options.h"
#include "rtd/eval/compare.h"
#include "synthetic/synthetic.h"
#ifdef HAVE_RTDENOISE_RENDER
#include "rtd/render/render.h"
#endif

namespace rtd::cli {

namespace fs = std::filesystem;

eval::Comparison runComparisonWithProgress(const eval::FrameSource& source, const eval::CompareSettings& cs,
                                           const std::string& what);
void writeComparison(const eval::Comparison& c, const fs::path& outDir);
std::vector<std::string> splitList(const std::string& s);

namespace {
#ifdef HAVE_RTDENOISE_RENDER
constexpr const char* kDefaultScene = "dynamic";  // the renderer's demo scene
#else
constexpr const char* kDefaultScene = "synthetic";
#endif

struct DemoOptions {
  std::string out = "rtdenoise-demo";
  std::string scene = kDefaultScene;
  std::string size;  // default: the scene's (synthetic: 640x360)
  int frames = 0;    // default: the scene's (synthetic: 48)
  // References: 1024 spp or 4 s per frame, whichever comes first; 48 frames stay within the
  // demo's 10-minute budget on 2 cores (about 3 minutes of it), and are cached for later runs.
  int referenceSpp = 1024;
  double referenceSeconds = 4.0;
  std::string cacheDir;
  int threads = 0;
  std::string methods;
  bool saveScene = false;
  EvalOptions eval;
};

/// Wraps a source so that every frame it loads is also written: the input as a native sequence
/// in <dir>/input, the reference as RGB EXRs in <dir>/reference (for `rtdenoise eval|compare`).
eval::FrameSource savedWhileLoading(eval::FrameSource src, const fs::path& dir) {
  auto writer = std::make_shared<SequenceWriter>(dir / "input");
  fs::create_directories(dir / "reference");
  src.load = [load = src.load, writer, dir](int index, Image& reference) {
    Frame f = load(index, reference);
    writer->write(f);
    writer->finish();
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", f.number);
    writeRgbExr(dir / "reference" / name, reference);
    return f;
  };
  return src;
}

/// The analytic scene of src/synthetic: exact features and motion, a noise-free reference
/// computed in closed form (nothing to cache).
eval::FrameSource syntheticScene(const DemoOptions& o) {
  const auto [w, h] = parseSize(o.size.empty() ? "640x360" : o.size);
  const int frames = o.frames > 0 ? o.frames : 48;
  if (frames < 2) throw Error("--frames " + std::to_string(frames) + ": the demo needs at least 2 frames");
  synthetic::Scene scene;
  scene.width = w;
  scene.height = h;
  eval::FrameSource src;
  src.description = "built-in analytic scene (camera translating over a checkered floor, wall and sphere; "
                    "exponential 1-spp-like noise; exact reference), " +
                    std::to_string(w) + "x" + std::to_string(h);
  src.frameCount = frames;
  src.load = [scene](int index, Image& reference) { return synthetic::makeFrame(scene, index, &reference); };
  return src;
}

#ifdef HAVE_RTDENOISE_RENDER
/// A built-in (or file) scene of the path tracer: 1-spp inputs rendered frame by frame and
/// references of `referenceSpp` samples (at most `referenceSeconds` each), read from and written
/// to the reference cache so a second run renders only the inputs.
eval::FrameSource renderedScene(const DemoOptions& o) {
  auto scene = render::Scene::load(o.scene);
  render::RenderSettings rs = scene->suggestedSettings();
  if (!o.size.empty()) std::tie(rs.width, rs.height) = parseSize(o.size);
  rs.spp = 1;
  const int frames = o.frames > 0 ? std::min(o.frames, scene->frameCount()) : scene->frameCount();
  if (frames < 2) throw Error("--frames " + std::to_string(frames) + ": the demo needs at least 2 frames");
  auto renderer = std::make_shared<render::Renderer>(scene, rs);
  render::ReferenceCache cache;
  cache.dir = o.cacheDir.empty() ? render::ReferenceCache::defaultDir() : fs::path(o.cacheDir);
  eval::FrameSource src;
  src.description = "path-traced scene '" + scene->name() + "' (1 spp input; reference " +
                    std::to_string(o.referenceSpp) + " spp" +
                    (o.referenceSeconds > 0 ? " or " + std::to_string(o.referenceSeconds).substr(0, 4) + " s" : "") +
                    " per frame, cached in " + cache.dir.string() + "), " + std::to_string(rs.width) + "x" +
                    std::to_string(rs.height);
  src.frameCount = frames;
  src.load = [scene, renderer, cache, spp = o.referenceSpp, seconds = o.referenceSeconds](int index, Image& reference) {
    Frame f = renderer->render(index);
    const fs::path entry = cache.entry(*scene, renderer->settings(), index, spp, render::Eye::Center, seconds);
    if (fs::exists(entry)) {
      try {
        reference = readRgbExr(entry);
        if (reference.width == f.width && reference.height == f.height) return f;
      } catch (const Error&) {
        // A damaged cache entry is rendered again and overwritten.
      }
    }
    reference = renderer->renderReference(index, spp, seconds);
    fs::create_directories(entry.parent_path());
    writeRgbExr(entry, reference);
    return f;
  };
  return src;
}
#endif

/// THE DEMO'S SCENE SOURCE (the one place that decides what the demo renders): the default
/// built-in animated scene as input frames plus references. With the path tracer built, the
/// renderer's "dynamic" scene (moving ball, spinning box, moving light) with cached references;
/// `--scene synthetic` (or a build without the renderer) uses the analytic scene.
eval::FrameSource demoScene(const DemoOptions& o) {
  eval::FrameSource src;
  if (o.scene == "synthetic") {
    src = syntheticScene(o);
  } else {
#ifdef HAVE_RTDENOISE_RENDER
    src = renderedScene(o);
#else
    throw Error("--scene '" + o.scene + "': this build has no path tracer; use --scene synthetic");
#endif
  }
  if (o.saveScene) src = savedWhileLoading(src, fs::path(o.out) / "scene");
  return src;
}

void run(const DemoOptions& o) {
  eval::CompareSettings cs;
  cs.methods = splitList(o.methods);  // empty: every method with a CPU implementation
  cs.threads = o.threads;
  cs.eval = o.eval.settings();
  std::vector<std::string> names = cs.methods;
  if (names.empty())
    for (const auto& m : listMethods())
      if (m.cpu) names.push_back(m.name);
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  const auto source = demoScene(o);
  std::fprintf(stderr, "rtdenoise demo: %d frames of %s; methods: %s\n", source.frameCount,
               source.description.c_str(), list.c_str());
  auto c = runComparisonWithProgress(source, cs, "demo: denoise + evaluate");
  c.title = "rtdenoise demo";
  std::fprintf(stderr, "writing the report...\n");
  writeComparison(c, o.out);
}
}  // namespace

void addDemo(CLI::App& app) {
  auto o = std::make_shared<DemoOptions>();
  auto* cmd = app.add_subcommand("demo", "render the built-in scene, run every method, evaluate, write the HTML report");
  cmd->add_option("--out,--output,-o", o->out, "output directory (report.html, metrics.json)")->capture_default_str();
  cmd->add_option("--scene", o->scene,
                  "'synthetic' (analytic scene) or a path tracer scene: built-in name, .gltf/.glb or .json")
      ->capture_default_str();
  cmd->add_option("--size", o->size, "WIDTHxHEIGHT (default: the scene's; synthetic 640x360)");
  cmd->add_option("--frames", o->frames, "number of frames (default: the scene's; synthetic 48)");
  cmd->add_option("--reference-spp", o->referenceSpp, "path tracer: reference samples per pixel")->capture_default_str();
  cmd->add_option("--reference-seconds", o->referenceSeconds, "path tracer: time budget per reference frame (0: none)")
      ->capture_default_str();
  cmd->add_option("--reference-cache", o->cacheDir,
                  "path tracer: reference cache directory (default $RTD_CACHE_DIR or ~/.cache/rtdenoise/references)");
  cmd->add_option("--methods,-m", o->methods, "comma-separated methods (default: every CPU method)");
  cmd->add_option("--threads", o->threads, "CPU threads (0 = all)")->capture_default_str();
  cmd->add_flag("--save-scene", o->saveScene,
                "also write the scene: <out>/scene/input (native sequence) and <out>/scene/reference (EXRs); "
                "large: about 10 MB per 480x270 frame");
  o->eval.add(cmd);
  cmd->callback([o] { run(*o); });
}

}  // namespace rtd::cli
#endif
