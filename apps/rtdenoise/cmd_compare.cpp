// rtdenoise compare: several methods (and backends) on one sequence -> HTML report + JSON.
#ifdef HAVE_RTDENOISE_EVAL
#include <filesystem>
#include <sstream>

#include "cli.h"
#include "eval_options.h"
#include "rtd/eval/compare.h"

namespace rtd::cli {

namespace fs = std::filesystem;

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

eval::Comparison runComparisonWithProgress(const eval::FrameSource& source, const eval::CompareSettings& cs,
                                           const std::string& what) {
  Progress progress(what, source.frameCount);
  auto c = eval::runComparison(source, cs, [&](int done, int, const std::string& detail) { progress.update(done, detail); });
  progress.finish();
  return c;
}

void writeComparison(const eval::Comparison& c, const fs::path& outDir) {
  fs::create_directories(outDir);
  eval::writeHtmlReport(c, outDir / "report.html");
  writeFileAtomic(outDir / "metrics.json", eval::comparisonJson(c));
  std::printf("%s", eval::comparisonTable(c).c_str());
  std::printf("report: %s\nmetrics: %s\n", fs::absolute(outDir / "report.html").string().c_str(),
              fs::absolute(outDir / "metrics.json").string().c_str());
}

namespace {
struct Options {
  std::string input, reference, out = "rtdenoise-compare", methods, backends = "cpu", crop;
  std::vector<std::string> settings;
  int frames = 0, frame = -1, threads = 0;
  EvalOptions eval;
};

void run(const Options& o) {
  eval::CompareSettings cs;
  cs.methods = splitList(o.methods);
  cs.backends.clear();
  for (const auto& b : splitList(o.backends)) cs.backends.push_back(parseBackend(b));
  if (cs.backends.empty()) throw Error("--backends: give at least one of cpu, vulkan");
  cs.settings = o.settings;
  cs.threads = o.threads;
  cs.eval = o.eval.settings();
  cs.shownFrame = o.frame;
  if (!o.crop.empty() && std::sscanf(o.crop.c_str(), "%d,%d,%d,%d", &cs.cropX, &cs.cropY, &cs.cropWidth, &cs.cropHeight) != 4)
    throw Error("--crop '" + o.crop + "': expected X,Y,WIDTH,HEIGHT");
  const auto source = eval::directorySource(o.input, o.reference, o.frames);
  writeComparison(runComparisonWithProgress(source, cs, "compare"), o.out);
}
}  // namespace

void addCompare(CLI::App& app) {
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("compare", "run several methods on one sequence; write an HTML report and JSON");
  cmd->add_option("--input,-i", o->input, "input sequence directory (native or Blender)")->required();
  cmd->add_option("--reference,-r", o->reference, "reference directory (frame EXRs or a sequence)")->required();
  cmd->add_option("--out,--output,-o", o->out, "output directory (report.html, metrics.json)")->capture_default_str();
  cmd->add_option("--methods,-m", o->methods, "comma-separated methods (default: every CPU method)");
  cmd->add_option("--backends,-b", o->backends, "comma-separated backends: cpu, vulkan")->capture_default_str();
  cmd->add_option("--set,-s", o->settings, "method.key=value or key=value (repeatable)");
  cmd->add_option("--frames", o->frames, "only the first N frames (0 = all)");
  cmd->add_option("--frame", o->frame, "frame index shown in the report's images (-1 = last)")->capture_default_str();
  cmd->add_option("--crop", o->crop, "enlarged crop X,Y,WIDTH,HEIGHT (default: centred)");
  cmd->add_option("--threads", o->threads, "CPU threads (0 = all)")->capture_default_str();
  o->eval.add(cmd);
  cmd->callback([o] { run(*o); });
}

}  // namespace rtd::cli
#endif
