// rtdenoise eval: metrics of a denoised sequence (and optionally the noisy input) against a reference.
#ifdef HAVE_RTDENOISE_EVAL
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "eval_options.h"
#include "rtd/eval/metrics.h"
#include "rtd/eval/reflections.h"

namespace rtd::cli {

namespace {
struct EvalCommandOptions {
  std::string reference, result, input, json;
  EvalOptions eval;
  // Reflections (docs/evaluation.md "Reflections"): both read the --input sequence.
  bool reflectionMotion = false, noLdspScaling = false, lineReference = false, eq23Subpixel = false;
  float maskRoughness = 0;
};

// PSNR and SSIM of the result over the input's pixels of roughness < r (steady frames).
nlohmann::json maskedMetrics(const EvalCommandOptions& o, const eval::EvalSettings& settings) {
  auto input = SequenceReader::open(o.input);
  auto result = eval::RgbSequence::open(o.result, "result");
  auto reference = eval::RgbSequence::open(o.reference, "reference");
  double psnr = 0, ssim = 0;
  int n = 0;
  for (int i = 0; i < result->frameCount(); ++i) {
    if (i < settings.warmupFrames) continue;
    const int number = result->frameNumber(i);
    const int ii = [&] {
      for (int k = 0; k < input->frameCount(); ++k)
        if (input->frameNumber(k) == number) return k;
      throw Error("--mask-roughness: no frame " + std::to_string(number) + " in input '" + o.input + "'");
    }();
    const int ri = reference->indexOf(number);
    if (ri < 0) throw Error("reference: no frame " + std::to_string(number) + " in '" + o.reference + "'");
    const Image mask = eval::reflectiveMask(input->read(ii), o.maskRoughness);
    const Image a = eval::toneMap(result->read(i), settings.toneMap), b = eval::toneMap(reference->read(ri), settings.toneMap);
    const double p = eval::maskedPsnr(a, b, mask), s = eval::maskedSsim(a, b, mask);
    if (!std::isfinite(s)) continue;  // no reflective pixel in this frame
    psnr += p;
    ssim += s;
    ++n;
  }
  std::printf("reflective pixels (roughness < %g), %d steady frames: PSNR %.2f dB, SSIM %.4f\n", o.maskRoughness, n,
              n ? psnr / n : NAN, n ? ssim / n : NAN);
  return {{"maskRoughness", o.maskRoughness}, {"frames", n}, {"psnr", n ? psnr / n : NAN}, {"ssim", n ? ssim / n : NAN}};
}

nlohmann::json reflectionMotion(const EvalCommandOptions& o) {
  eval::ReflectionMotionSettings s;
  s.ldspScaling = !o.noLdspScaling;
  s.referenceOnRay = !o.lineReference;
  s.subpixelFit = o.eq23Subpixel ? SvgfSubpixelFit::inverseDistance : SvgfSubpixelFit::quadratic;
  auto input = SequenceReader::open(o.input);
  const auto frames = eval::reflectionMotionError(*input, s);
  nlohmann::json per = nlohmann::json::array();
  double err = 0, within = 0;
  uint64_t pixels = 0, missed = 0;
  int n = 0;
  for (const auto& f : frames) {
    per.push_back({{"number", f.number}, {"pixels", f.pixels}, {"missed", f.missed}, {"meanError", f.meanError},
                   {"withinOnePixel", f.withinOnePixel}, {"meanTaps", f.meanTaps}});
    pixels += f.pixels;
    missed += f.missed;
    if (!f.pixels || !(f.meanError >= 0)) continue;
    err += f.meanError;
    within += f.withinOnePixel;
    ++n;
  }
  std::printf("reflection motion vs brute force (%s LDSP scaling, %s reference), %d frames: mean error %.3f px, %.1f%% within 1 px, "
              "%.2f%% missed\n",
              s.ldspScaling ? "with" : "without", s.referenceOnRay ? "ray" : "line", n, n ? err / n : NAN, n ? 100.0 * within / n : NAN,
              pixels ? 100.0 * double(missed) / double(pixels) : NAN);
  return {{"ldspScaling", s.ldspScaling}, {"subpixelFit", s.subpixelFit == SvgfSubpixelFit::quadratic ? "quadratic" : "inverseDistance"},
          {"bruteForceWindow", 2 * s.bruteForceRadius},
          {"reference", s.referenceOnRay ? "ray" : "line"}, {"frames", per},
          {"meanError", n ? err / n : NAN}, {"withinOnePixel", n ? within / n : NAN},
          {"missed", pixels ? double(missed) / double(pixels) : NAN}};
}

void runEval(const EvalCommandOptions& o) {
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
  std::string text = eval::metricsJson(streams, settings);
  if (o.reflectionMotion || o.maskRoughness > 0) {
    nlohmann::json j = nlohmann::json::parse(text);
    if (o.maskRoughness > 0) j["reflectivePixels"] = maskedMetrics(o, settings);
    if (o.reflectionMotion) j["reflectionMotion"] = reflectionMotion(o);
    text = j.dump(1);
  }
  if (!o.json.empty()) {
    writeFileAtomic(o.json, text);
    std::printf("wrote %s\n", o.json.c_str());
  }
}
}  // namespace

void addEval(CLI::App& app) {
  auto o = std::make_shared<EvalCommandOptions>();
  auto* cmd = addSubcommand(app, "eval", "metrics of a result sequence against a reference (table, and JSON with --json)");
  cmd->add_option("--reference,-r", o->reference, "reference directory (frame images or a sequence)")->required();
  cmd->add_option("--result", o->result, "result directory (e.g. `rtdenoise denoise` output)")->required();
  auto* input = cmd->add_option("--input,-i", o->input, "noisy input sequence, evaluated as a second row");
  cmd->add_option("--json", o->json, "FILE: also write per-frame metrics and summaries as JSON to FILE (nothing is written without it)");
  o->eval.add(cmd);
  cmd->add_flag("--reflection-motion", o->reflectionMotion,
                "also compare the input's reflection motion vectors (diamond search) with the brute-force search "
                "(Voorhuis Sec. 7.4; needs the renderer's reflection buffers)")
      ->needs(input);
  auto* motion = cmd->get_option("--reflection-motion");
  cmd->add_flag("--no-ldsp-scaling", o->noLdspScaling, "with --reflection-motion: the plain LDSP (Figs. 12-13)")->needs(motion);
  cmd->add_flag("--eq23-subpixel", o->eq23Subpixel,
                "with --reflection-motion: both searches refine by Voorhuis Eqs. 2-3 instead of the quadratic fit "
                "(SVGF's subpixelFit)")
      ->needs(motion);
  cmd->add_flag("--line-reference", o->lineReference,
                "with --reflection-motion: the reference measures glossy pixels by Eq. 5 as written (to the far "
                "representative ray's whole line, as the search) instead of to its half-line")
      ->needs(motion);
  cmd->add_option("--mask-roughness", o->maskRoughness,
                  "also PSNR / SSIM over the input's pixels of roughness below this (0.4: reflective pixels)")
      ->needs(input)
      ->check(CLI::Range(0.0f, 1.01f));
  cmd->callback([o] { runEval(*o); });
}

}  // namespace rtd::cli
#endif
