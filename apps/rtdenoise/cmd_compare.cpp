// rtdenoise compare: several configurations (methods, settings, backends) on one sequence ->
// one HTML report + JSON.
#ifdef HAVE_RTDENOISE_EVAL
#include <filesystem>

#include "cli.h"
#include "compare_common.h"
#include "eval_options.h"

namespace rtd::cli {

namespace fs = std::filesystem;

namespace {
struct CompareOptions {
  std::string input, reference, crop;
  OutputOptions output;
  std::vector<std::string> methods, settings;
  std::string json;
  DeviceOptions device;
  int frames = 0, frame = -1;
  EvalOptions eval;
};

void runCompare(const CompareOptions& o) {
  eval::CompareSettings cs = compareSettings(o.methods, o.settings, o.device);
  const auto source = eval::directorySource(o.input, o.reference, framesToUse(o.frames, SequenceReader::open(o.input)->frameCount()));
  cs.eval = o.eval.settings(source.frameCount);
  cs.shownFrame = shownFrameIndex(o.frame, source.frameCount);
  if (!o.crop.empty()) parseCrop(o.crop, source.width, source.height, cs);
  o.output.prepare(kComparisonOutputs);
  writeComparison(runComparisonWithProgress(source, cs, "compare"), o.output.dir, o.json);
}
}  // namespace

void addCompare(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  auto* cmd = addSubcommand(app, "compare", "run several configurations on one sequence; write an HTML report and JSON");
  cmd->add_option("--input,-i", o->input, "input sequence directory (native, per-buffer files or Blender)")->required();
  cmd->add_option("--reference,-r", o->reference, "reference directory (frame images or a sequence)")->required();
  o->output.add(cmd, "report.html, metrics.json");
  addConfigurationOptions(cmd, o->methods, o->settings);
  o->device.add(cmd, true);
  cmd->add_option("--frames", o->frames, "only the first N frames (0 = all)")->capture_default_str();
  cmd->add_option("--frame", o->frame, "frame index (0-based) the report opens at (-1 = last)")->capture_default_str();
  cmd->add_option("--crop", o->crop, "enlarged crop X,Y,WIDTH,HEIGHT inside the image (default: centred)");
  cmd->add_option("--json", o->json, "FILE: write the metrics JSON to FILE (default: <output>/metrics.json)");
  o->eval.add(cmd);
  cmd->callback([o] { runCompare(*o); });
}

}  // namespace rtd::cli
#endif
