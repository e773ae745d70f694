// rtdenoise eval: metrics of a denoised sequence (and optionally the noisy input) against a reference.
#ifdef HAVE_RTDENOISE_EVAL
#include <filesystem>

#include "cli.h"
#include "eval_options.h"

namespace rtd::cli {

namespace {
struct Options {
  std::string reference, result, input, json;
  EvalOptions eval;
};

void run(const Options& o) {
  const auto settings = o.eval.settings(eval::RgbSequence::open(o.result, "result")->frameCount());
  std::unique_ptr<Progress> bar;
  const auto streams = eval::evaluateDirectories(
      o.reference, o.result, o.input.empty() ? std::nullopt : std::optional<std::filesystem::path>(o.input), settings,
      [&](int done, int total) {
        if (!bar) bar = std::make_unique<Progress>("eval", total);
        bar->update(done);
      });
  if (bar) bar->finish();
  std::printf("%s", eval::summaryTable(streams, settings).c_str());
  if (!o.json.empty()) {
    writeFileAtomic(o.json, eval::metricsJson(streams, settings));
    std::printf("wrote %s\n", o.json.c_str());
  }
}
}  // namespace

void addEval(CLI::App& app) {
  auto o = std::make_shared<Options>();
  auto* cmd = addSubcommand(app, "eval", "metrics of a result sequence against a reference (table, and JSON with --json)");
  cmd->add_option("--reference,-r", o->reference, "reference directory (frame images or a sequence)")->required();
  cmd->add_option("--result", o->result, "result directory (e.g. `rtdenoise denoise` output)")->required();
  cmd->add_option("--input,-i", o->input, "noisy input sequence, evaluated as a second row");
  cmd->add_option("--json", o->json, "FILE: also write per-frame metrics and summaries as JSON to FILE (nothing is written without it)");
  o->eval.add(cmd);
  cmd->callback([o] { run(*o); });
}

}  // namespace rtd::cli
#endif
