// rtdenoise demo: the README's main job. Makes the built-in animated scene, runs every
// implemented method on it, evaluates them against the reference and writes the HTML report.
#ifdef HAVE_RTDENOISE_EVAL
#include <filesystem>

#include "cli.h"
#include "eval_options.h"
#include "rtd/eval/compare.h"
#include "synthetic/synthetic.h"

namespace rtd::cli {

namespace fs = std::filesystem;

eval::Comparison runComparisonWithProgress(const eval::FrameSource& source, const eval::CompareSettings& cs,
                                           const std::string& what);
void writeComparison(const eval::Comparison& c, const fs::path& outDir);
std::vector<std::string> splitList(const std::string& s);

namespace {
struct DemoOptions {
  std::string out = "rtdenoise-demo";
  std::string size = "640x360";
  int frames = 48;
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

/// THE DEMO'S SCENE SOURCE (the one place to switch to the path tracer): the default
/// built-in animated scene as input frames plus references. Today: the analytic scene of
/// src/synthetic (exact features and motion, noise-free reference computed in closed form,
/// so nothing needs caching). With the renderer, this renders the default scene's 1-spp
/// inputs and its many-spp references into <out>/scene, reusing cached references.
eval::FrameSource demoScene(const DemoOptions& o) {
  const auto [w, h] = parseSize(o.size);
  if (o.frames < 2) throw Error("--frames " + std::to_string(o.frames) + ": the demo needs at least 2 frames");
  synthetic::Scene scene;
  scene.width = w;
  scene.height = h;
  eval::FrameSource src;
  src.description = "built-in analytic scene (camera translating over a checkered floor, wall and sphere; "
                    "exponential 1-spp-like noise; exact reference), " +
                    std::to_string(w) + "x" + std::to_string(h);
  src.frameCount = o.frames;
  src.load = [scene](int index, Image& reference) { return synthetic::makeFrame(scene, index, &reference); };
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
  std::fprintf(stderr, "rtdenoise demo: %d frames of the built-in scene at %s; methods: %s\n", o.frames,
               o.size.c_str(), list.c_str());
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
  cmd->add_option("--size", o->size, "WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--frames", o->frames, "number of frames")->capture_default_str();
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
