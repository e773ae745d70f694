// rtdenoise render: path-trace a scene's animation into a native sequence (1-spp color plus
// every feature buffer) and, optionally, cached high-sample references (docs/renderer.md).
#ifdef HAVE_RTDENOISE_RENDER
#include <tbb/global_control.h>

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "rtd/guide_rays.h"
#include "rtd/render/render.h"

namespace rtd::cli {

namespace {

// "cornell, pillars, ...": the built-in scenes for the help text.
std::string builtinList() {
  std::string list;
  for (const auto& n : render::Scene::builtinScenes()) list += (list.empty() ? "" : ", ") + n;
  return list;
}

namespace fs = std::filesystem;
using render::Eye;

struct RenderOptions {
  std::string scene;
  OutputOptions output;
  std::string size;
  int frames = 0;
  int spp = 1;
  int referenceSpp = 0;
  double referenceSeconds = 0;
  int maxDepth = 0;
  int seed = -1;
  float sampleFraction = 1.0f;
  bool stereo = false;
  bool hiddenArea = false;
  float eyeDistance = -1;
  bool jitter = false;
  bool guideRays = false;
  bool minimal = false;
  int threads = 0;
  std::string cacheDir;
  bool noCache = false;
  std::string printScene;
};

/// What `render` writes into its output directory (and --overwrite replaces).
const std::vector<std::string> kRenderOutputs = {R"(frame_\d+\.exr)", R"(sequence\.json)", R"(render\.json)",
                                                 "reference", "left", "right"};

/// Renders (or fetches from the cache) the reference of one frame.
Image reference(render::Renderer& r, const render::Scene& scene, const RenderOptions& o, const render::ReferenceCache& cache,
                int index, Eye eye, int& sppTaken, bool& cached) {
  Image img = cache.fetchOrRender(r, scene, index, o.referenceSpp, o.referenceSeconds, eye, &cached);
  sppTaken = cached ? -1 : r.stats().samplesPerPixel;
  return img;
}

void runRender(const RenderOptions& o, const CLI::App& cmd) {
  if (!o.printScene.empty()) {
    for (const char* other : {"--scene", "--output", "--frames", "--size", "--reference-spp"})
      if (cmd.count(other)) throw UsageError(std::string("--print-scene prints a description and renders nothing: drop ") + other);
    const std::string text = render::Scene::builtinDescription(o.printScene);
    if (text.empty()) throw UsageError("--print-scene '" + o.printScene + "': not a built-in scene");
    std::printf("%s\n", text.c_str());
    return;
  }
  if (o.scene.empty()) throw UsageError("--scene is required (unless --print-scene)");
  if (o.output.dir.empty()) throw UsageError("--output is required (unless --print-scene)");
  if (o.referenceSeconds > 0 && o.referenceSpp == 0)
    throw UsageError("--reference-seconds limits the references: give --reference-spp too");
  if (o.referenceSpp == 0 && cmd.count("--reference-cache"))
    throw UsageError("--reference-cache concerns references: give --reference-spp too");
  if (cmd.count("--reference-cache") && o.noCache) throw UsageError("--reference-cache and --no-reference-cache contradict each other");
  if (cmd.count("--eye-distance") && !o.stereo) throw UsageError("--eye-distance needs --stereo");
  if (o.guideRays && o.spp < 2) throw UsageError("--guide-rays needs --spp 2 or more (sample 0 is the guide ray)");
  if (o.guideRays && (o.stereo || o.jitter || o.sampleFraction < 1.0f))
    throw UsageError("--guide-rays traces every pixel's centre once per eye: not with --stereo, --jitter or --sample-fraction");
  std::unique_ptr<tbb::global_control> threads;
  if (o.threads > 0) threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(o.threads));

  auto scene = render::Scene::load(o.scene);
  render::RenderSettings s = scene->suggestedSettings();
  if (!o.size.empty()) std::tie(s.width, s.height) = parseSize(o.size);
  s.spp = o.spp;
  if (o.maxDepth > 0) s.maxDepth = o.maxDepth;
  if (o.seed >= 0) s.seed = uint32_t(o.seed);
  s.sampleFraction = o.sampleFraction;
  s.hiddenArea = o.hiddenArea;
  if (o.eyeDistance >= 0) s.eyeDistance = o.eyeDistance;
  s.pixelJitter = s.pixelJitter || o.jitter;
  s.guideRays = o.guideRays;
  s.allBuffers = !o.minimal;
  const int frames = o.frames > 0 ? o.frames : scene->frameCount();
  render::Renderer renderer(scene, s);
  render::ReferenceCache cache;
  if (!o.noCache) cache.dir = o.cacheDir.empty() ? render::ReferenceCache::defaultDir() : fs::path(o.cacheDir);

  o.output.prepare(kRenderOutputs);
  const fs::path out(o.output.dir);
  std::vector<std::pair<Eye, fs::path>> eyes;
  if (o.stereo) eyes = {{Eye::Left, out / "left"}, {Eye::Right, out / "right"}};
  else eyes = {{Eye::Center, out}};

  const int steps = frames * int(eyes.size()) * (o.referenceSpp > 0 ? 2 : 1);
  Progress progress("render " + scene->name(), steps);
  int done = 0;
  double renderSeconds = 0;
  uint64_t rays = 0;
  for (const auto& [eye, dir] : eyes) {
    fs::create_directories(dir);
    SequenceWriter writer(dir);
    std::unique_ptr<SequenceWriter> refWriter;
    if (o.referenceSpp > 0) {
      fs::create_directories(dir / "reference");
      refWriter = std::make_unique<SequenceWriter>(dir / "reference");
    }
    nlohmann::json refSpp = nlohmann::json::array();
    for (int i = 0; i < frames; ++i) {
      GuideRaySamples samples;
      Frame f = o.guideRays ? renderer.render(i, eye, samples) : renderer.render(i, eye);
      renderSeconds += renderer.stats().seconds;
      rays += renderer.stats().rays;
      writer.write(f, o.guideRays ? &samples : nullptr);
      writer.finish();
      progress.update(++done, "frame " + std::to_string(i + 1) + (o.stereo ? std::string(" ") + render::eyeName(eye) : ""));
      if (refWriter) {
        int taken = 0;
        bool cached = false;
        Frame ref;
        ref.number = f.number;
        ref.width = f.width;
        ref.height = f.height;
        ref.camera = f.camera;
        ref[Buffer::Color] = reference(renderer, *scene, o, cache, i, eye, taken, cached);
        refSpp.push_back(taken);
        refWriter->write(ref);
        refWriter->finish();
        progress.update(++done, std::string("reference ") + std::to_string(i + 1) + (cached ? " (cached)" : ""));
      }
    }
    nlohmann::json meta = {{"generator", "rtdenoise render"},
                           {"scene", o.scene},
                           {"sceneName", scene->name()},
                           {"eye", render::eyeName(eye)},
                           {"eyeDistance", o.stereo ? s.eyeDistance : 0.0f},
                           {"frames", frames},
                           {"width", s.width},
                           {"height", s.height},
                           {"spp", s.spp},
                           {"guideRays", s.guideRays},
                           {"maxDepth", s.maxDepth},
                           {"seed", s.seed},
                           {"pixelJitter", s.pixelJitter},
                           {"sampleFraction", s.sampleFraction},
                           {"hiddenArea", s.hiddenArea},
                           {"seedBits", 24}};
    if (refWriter)
      meta["reference"] = {{"dir", "reference"}, {"spp", o.referenceSpp}, {"secondsBudget", o.referenceSeconds},
                           {"samplesTaken", refSpp}, {"note", "samplesTaken -1: read from the reference cache"}};
    writeFileAtomic(dir / "render.json", meta.dump(1) + "\n");
  }
  if (o.stereo) {
    nlohmann::json top = {{"generator", "rtdenoise render"}, {"stereo", true}, {"left", "left"}, {"right", "right"},
                          {"eyeDistance", s.eyeDistance}, {"frames", frames}};
    writeFileAtomic(out / "render.json", top.dump(1) + "\n");
  }
  const double rps = renderSeconds > 0 ? double(rays) / renderSeconds : 0.0;
  progress.finish();
  std::printf("rendered %d frame(s) of '%s' at %dx%d, %d spp%s: %.3f s/frame, %.2f Mrays/s -> %s\n", frames * int(eyes.size()),
              scene->name().c_str(), s.width, s.height, s.spp, o.stereo ? " (stereo)" : "",
              renderSeconds / (frames * eyes.size()), rps * 1e-6, out.string().c_str());
}

}  // namespace

void addRender(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  auto* cmd = addSubcommand(app, "render", "path-trace a scene into a native sequence (1-spp input, features, references)");
  cmd->add_option("--scene", o->scene, "REQUIRED (unless --print-scene): built-in scene (" + builtinList() + "), .gltf/.glb or .json description");
  o->output.add(cmd, "REQUIRED (unless --print-scene): a native sequence; stereo: <dir>/left and <dir>/right", false);
  cmd->add_option("--frames", o->frames, "number of frames (default: the scene's)")->check(atLeast(1));
  cmd->add_option("--size", o->size, "WxH (default: the scene's, 320x180 for built-in scenes)");
  cmd->add_option("--spp", o->spp, "samples per pixel of the noisy color")->default_val(1)->check(atLeast(1));
  cmd->add_option("--reference-spp", o->referenceSpp, "also render references with this many samples per pixel (0: none)")
      ->check(atLeast(0));
  cmd->add_option("--reference-seconds", o->referenceSeconds, "time budget per reference frame in seconds (0: none)")
      ->check(atLeast(0));
  cmd->add_option("--max-depth", o->maxDepth, "maximum path depth (default 8)")->check(atLeast(1));
  cmd->add_option("--seed", o->seed, "global random seed (default: the scene's, 1)")->check(atLeast(0));
  cmd->add_option("--sample-fraction", o->sampleFraction, "fraction of pixels traced per frame (sparse, blue-noise mask)")
      ->default_val(1.0f)->check(CLI::Range(1e-6f, 1.0f));
  cmd->add_flag("--stereo", o->stereo, "render left and right eyes into <output>/left and <output>/right");
  cmd->add_flag("--hidden-area", o->hiddenArea, "a synthetic HMD hidden-area mesh: lens border and nose not traced (buffer hiddenArea)");
  cmd->add_option("--eye-distance", o->eyeDistance, "stereo eye distance in world units (default 0.064; with --stereo)")
      ->check(atLeast(0));
  cmd->add_flag("--jitter", o->jitter, "jitter primary rays within the pixel (default: pixel centres)");
  cmd->add_flag("--guide-rays", o->guideRays,
                "supersampling with guide rays (Voorhuis Sec. 5): color holds sample 0 through the pixel centre, "
                "the frames also hold the other --spp - 1 jittered samples, which `denoise` mixes in");
  cmd->add_flag("--minimal", o->minimal, "write only color and the standard feature buffers");
  cmd->add_option("--threads", o->threads, "CPU threads (0 = all cores)")->capture_default_str()->check(atLeast(0));
  cmd->add_option("--reference-cache", o->cacheDir, "reference cache directory (default $RTD_CACHE_DIR or ~/.cache/rtdenoise/references)");
  cmd->add_flag("--no-reference-cache", o->noCache, "do not read or write the reference cache");
  cmd->add_option("--print-scene", o->printScene, "print a built-in scene's JSON description and exit");
  cmd->callback([o, cmd] { runRender(*o, *cmd); });
}

}  // namespace rtd::cli

#endif  // HAVE_RTDENOISE_RENDER
