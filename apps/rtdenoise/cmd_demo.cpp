// rtdenoise demo: the README's main job. Makes the built-in animated scene, runs every
// implemented method on it, evaluates them against the reference and writes the HTML report.
#ifdef HAVE_RTDENOISE_EVAL
#include <filesystem>

#include "cli.h"
#include "compare_common.h"
#include "eval_options.h"
#include "synthetic/synthetic.h"
#ifdef HAVE_RTDENOISE_RENDER
#include "rtd/render/render.h"
#endif

namespace rtd::cli {

namespace fs = std::filesystem;

namespace {
struct DemoOptions {
  OutputOptions output{"rtdenoise-demo"};
  std::string scene = "dynamic";
  std::string size = "320x180";
  int frames = 32;
  int referenceSpp = 256;  // 128 leaves visible caustic fireflies from the metal ball
  std::string cacheDir;
  bool noCache = false;
  DeviceOptions device;
  std::vector<std::string> methods, settings;
  std::string json;
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

/// The analytic scene of src/synthetic: exact features and motion, a closed-form reference.
eval::FrameSource syntheticScene(const DemoOptions& o, int w, int h) {
  synthetic::Scene scene;
  scene.width = w;
  scene.height = h;
  eval::FrameSource src;
  src.description = "analytic scene (camera translating over a checkered floor, wall and sphere; "
                    "exponential 1-spp-like noise; exact reference), " +
                    std::to_string(w) + "x" + std::to_string(h);
  src.frameCount = o.frames;
  src.load = [scene](int index, Image& reference) { return synthetic::makeFrame(scene, index, &reference); };
  src.referenceExact = true;
  return src;
}

/// The demo's scene source: the built-in animated scene rendered by the path tracer at 1 spp,
/// with references of `referenceSpp` samples taken from (or stored in) the reference cache, so a
/// second run renders no reference again. `--scene synthetic` uses the analytic scene instead.
eval::FrameSource demoScene(const DemoOptions& o) {
  const auto [w, h] = parseSize(o.size);
  eval::FrameSource src;
  if (o.scene == "synthetic") {
    src = syntheticScene(o, w, h);
  } else {
#ifdef HAVE_RTDENOISE_RENDER
    auto scene = render::Scene::load(o.scene);
    render::RenderSettings rs = scene->suggestedSettings();
    rs.width = w;
    rs.height = h;
    auto renderer = std::make_shared<render::Renderer>(scene, rs);
    render::ReferenceCache cache;
    if (!o.noCache) cache.dir = o.cacheDir.empty() ? render::ReferenceCache::defaultDir() : fs::path(o.cacheDir);
    src.description = "built-in scene '" + scene->name() + "' path traced at 1 spp, references at " +
                      std::to_string(o.referenceSpp) + " spp, " + std::to_string(w) + "x" + std::to_string(h);
    src.frameCount = o.frames;
    // The reference is the mean of two independent halves of referenceSpp / 2 samples (the
    // second from a renderer with another seed), so the report can estimate the reference's
    // own remaining noise from their difference (eval::ReferenceQuality).
    render::RenderSettings rsB = rs;
    rsB.seed = rs.seed + 7919u;
    auto rendererB = std::make_shared<render::Renderer>(scene, rsB);
    struct Halves {
      int index = -1;
      Image a, b;
    };
    auto halves = std::make_shared<Halves>();
    const int half = std::max(1, o.referenceSpp / 2);
    src.load = [renderer, rendererB, scene, cache, half, halves](int index, Image& reference) {
      Frame f = renderer->render(index);
      halves->a = cache.fetchOrRender(*renderer, *scene, index, half, 0.0, render::Eye::Center);
      halves->b = cache.fetchOrRender(*rendererB, *scene, index, half, 0.0, render::Eye::Center);
      halves->index = index;
      reference = halves->a;
      for (size_t i = 0; i < reference.pixels.size(); ++i) reference.pixels[i] = 0.5f * (halves->a.pixels[i] + halves->b.pixels[i]);
      return f;
    };
    src.referenceHalves = [halves](int index, Image& a, Image& b) {
      if (halves->index != index) throw Error("demo: reference halves asked for frame index " + std::to_string(index) + " before it was loaded");
      a = halves->a;
      b = halves->b;
    };
    src.referenceSpp = 2 * half;
    src.referenceNote = "Path traced with the renderer's reference mode (no firefly clamping). The metal ball's caustic "
                        "paths converge slowly, so isolated fireflies remain at this sample count; raise "
                        "--reference-spp (the references are cached) to push them down.";
#else
    throw Error("this build has no path tracer; use --scene synthetic");
#endif
  }
  src.width = w;
  src.height = h;
  if (o.saveScene) src = savedWhileLoading(src, fs::path(o.output.dir) / "scene");
  return src;
}

void runDemo(const DemoOptions& o) {
  eval::CompareSettings cs = compareSettings(o.methods, o.settings, o.device);
  cs.eval = o.eval.settings(o.frames);
  o.output.prepare(kComparisonOutputs);
  const auto source = demoScene(o);
  std::string list;
  for (const auto& m : o.methods) list += (list.empty() ? "" : ", ") + m;
  std::fprintf(stderr, "rtdenoise demo: %s, %d frames; methods: %s\n", source.description.c_str(), o.frames,
               list.empty() ? "every CPU method" : list.c_str());
  auto c = runComparisonWithProgress(source, cs, "demo: denoise + evaluate");
  c.title = "rtdenoise demo";
  writeComparison(c, o.output.dir, o.json);
}
}  // namespace

void addDemo(CLI::App& app) {
  auto o = std::make_shared<DemoOptions>();
  auto* cmd = addSubcommand(app, "demo", "render the built-in scene, run every method, evaluate, write the HTML report");
  o->output.add(cmd, "report.html, metrics.json", false);
  cmd->get_option("--output")->capture_default_str();
  cmd->add_option("--scene", o->scene, "built-in scene (see `rtdenoise render --help`), a scene file, or 'synthetic'")
      ->capture_default_str();
  cmd->add_option("--size", o->size, "WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--reference-spp", o->referenceSpp, "samples per pixel of the references")->capture_default_str()
      ->check(atLeast(1));
  cmd->add_option("--reference-cache", o->cacheDir, "reference cache directory (default $RTD_CACHE_DIR or ~/.cache/rtdenoise/references)");
  cmd->add_flag("--no-reference-cache", o->noCache, "do not read or write the reference cache");
  cmd->add_option("--frames", o->frames, "number of frames (>= 2)")->capture_default_str()->check(atLeast(2));
  addConfigurationOptions(cmd, o->methods, o->settings);
  o->device.add(cmd, true);
  cmd->add_option("--json", o->json, "FILE: write the metrics JSON to FILE (default: <output>/metrics.json)");
  cmd->add_flag("--save-scene", o->saveScene,
                "also write the scene: <output>/scene/input (native sequence) and <output>/scene/reference (EXRs); "
                "large: about 10 MB per 480x270 frame");
  o->eval.add(cmd);
  cmd->callback([o, cmd] {
    if (o->scene == "synthetic" && (cmd->count("--reference-spp") || cmd->count("--reference-cache")))
      throw UsageError("--scene synthetic has an exact reference: --reference-spp and --reference-cache do not apply");
    if (cmd->count("--reference-cache") && o->noCache)
      throw UsageError("--reference-cache and --no-reference-cache contradict each other");
    runDemo(*o);
  });
}

}  // namespace rtd::cli
#endif
