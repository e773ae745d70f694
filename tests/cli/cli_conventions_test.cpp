// The CLI's conventions (docs/cli.md): exit codes, refused output folders, presets applied
// first, unknown and meaningless options as usage errors, configurations in `compare`.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rtd/rtd.h"
#include "support/run_cli.h"
#include "synthetic/synthetic.h"
#include "support/files.h"

using namespace rtd;
using rtd::test::runCli;
namespace fs = std::filesystem;

namespace {

/// A native input sequence (the analytic scene) and its reference EXRs.
void writeScene(const fs::path& dir, int frames, int w = 24, int h = 16) {
  synthetic::Scene scene;
  scene.width = w;
  scene.height = h;
  SequenceWriter writer(dir / "input");
  fs::create_directories(dir / "reference");
  for (int i = 0; i < frames; ++i) {
    Image ref;
    writer.write(synthetic::makeFrame(scene, i, &ref));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", i + 1);
    writeRgbExr(dir / "reference" / name, ref);
  }
  writer.finish();
}


bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
}  // namespace

TEST(CliConventions, VersionUnknownSubcommandAndHelpFooter) {
  auto r = runCli("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_TRUE(contains(r.output, versionString())) << r.output;
  r = runCli("frobnicate --x");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.output, "unknown subcommand 'frobnicate'")) << r.output;
  // Every subcommand's help ends with the exit codes; required options are marked.
  for (const char* sub : {"denoise", "methods", "bench", "eval", "compare", "demo", "pack", "devices"}) {
    r = runCli(std::string(sub) + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_TRUE(contains(r.output, "Exit status: 0 success; 1 bad input")) << sub << "\n" << r.output;
  }
  EXPECT_TRUE(contains(runCli("denoise --help").output, "REQUIRED"));
  EXPECT_TRUE(contains(runCli("eval --help").output, "REQUIRED"));
}

TEST(CliConventions, MethodsFiltersByName) {
  auto r = runCli("methods bmfr");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "bmfr  ("));
  EXPECT_FALSE(contains(r.output, "svgf  ("));
  r = runCli("methods nope");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.output, "'nope'")) << r.output;
  r = runCli("methods svgf --json -");
  ASSERT_EQ(r.code, 0);
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j.size(), 1u);
  bool variantIsPreset = false;
  for (const auto& s : j[0]["settings"]) variantIsPreset |= s["name"] == "variant" && s["preset"] == true;
  EXPECT_TRUE(variantIsPreset);
}

TEST(CliConventions, PresetNeverOverridesASettingGivenWithIt) {
  auto device = Device::create();
  for (const auto& order : {std::vector<SettingAssignment>{{"sigmaNormal", "32"}, {"variant", "dundr"}},
                            std::vector<SettingAssignment>{{"variant", "dundr"}, {"sigmaNormal", "32"}}}) {
    auto d = device->createDenoiser("svgf");
    applySettings(*d, order);
    const auto s = d->getSettings<SvgfSettings>();
    EXPECT_EQ(s.variant, SvgfVariant::dundr);
    EXPECT_EQ(s.sigmaNormal, 32.0f);  // Dundr's preset alone gives 64
    EXPECT_EQ(s.kernel, SvgfSettings::forVariant(SvgfVariant::dundr).kernel);  // the rest of the preset applies
  }
  auto d = device->createDenoiser("svgf");
  EXPECT_THROW(applySettings(*d, {{"sigmaNormal", "32"}, {"sigmaNormal", "16"}}), Error);  // given twice
  EXPECT_THROW(applySettings(*d, {{"nope", "1"}}), Error);
  EXPECT_EQ(d->getSettings<SvgfSettings>().sigmaNormal, SvgfSettings{}.sigmaNormal);  // nothing applied

  // The same through the CLI: the settings denoise used are in timings.json.
  const fs::path dir = rtd::test::scratchDir("rtd_cliconv", "preset");
  writeScene(dir, 2);
  const auto r = runCli("denoise -m svgf -i " + (dir / "input").string() + " -o " + (dir / "out").string() +
                        " --set sigmaNormal=32 --set variant=dundr");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto t = rtd::test::readJson(dir / "out" / "timings.json");
  EXPECT_EQ(t["settings"]["variant"], "dundr");
  EXPECT_EQ(t["settings"]["sigmaNormal"], "32");
  fs::remove_all(dir);
}

TEST(CliConventions, ReusedOutputFolderIsRefusedUnlessOverwrite) {
  const fs::path dir = rtd::test::scratchDir("rtd_cliconv", "reuse");
  writeScene(dir, 4);
  const std::string in = (dir / "input").string(), out = (dir / "out").string();
  ASSERT_EQ(runCli("denoise -m accumulate -i " + in + " -o " + out).code, 0);
  // A second run into the same folder (here with fewer frames) would leave the old frames beside
  // the new ones: refused, and nothing is changed.
  auto r = runCli("denoise -m accumulate --frames 2 -i " + in + " -o " + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.output, "--overwrite")) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "frame_0004.exr"));
  // --overwrite replaces the earlier run's files: only the new frames remain.
  r = runCli("denoise -m accumulate --frames 2 --overwrite -i " + in + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "frame_0002.exr"));
  EXPECT_FALSE(fs::exists(dir / "out" / "frame_0003.exr"));
  EXPECT_FALSE(fs::exists(dir / "out" / "frame_0004.exr"));
  // Files rtdenoise did not write are never deleted, not even with --overwrite (here: the input).
  r = runCli("denoise -m accumulate --overwrite -i " + in + " -o " + in);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.output, "sequence.json")) << r.output;
  EXPECT_TRUE(fs::exists(dir / "input" / "frame_0001.exr"));
  fs::remove_all(dir);
}

TEST(CliConventions, EvalRefusesMixedOrMismatchedFrameLists) {
  const fs::path dir = rtd::test::scratchDir("rtd_cliconv", "mixed");
  writeScene(dir, 4);
  const std::string in = (dir / "input").string(), ref = (dir / "reference").string(), out = (dir / "out").string();
  ASSERT_EQ(runCli("denoise -m accumulate -i " + in + " -o " + out).code, 0);
  auto r = runCli("eval --reference " + ref + " --result " + out);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "metrics.json"));  // eval writes only where --json says
  EXPECT_FALSE(fs::exists(dir / "reference" / "metrics.json"));
  // A frame left over from another run: timings.json does not list it.
  fs::copy_file(dir / "out" / "frame_0004.exr", dir / "out" / "frame_0005.exr");
  writeRgbExr(dir / "reference" / "frame_0005.exr", readRgbExr(dir / "reference" / "frame_0004.exr"));
  r = runCli("eval --reference " + ref + " --result " + out);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.output, "timings.json")) << r.output;
  // A result that starts later than the reference.
  fs::remove(dir / "out" / "timings.json");
  fs::remove(dir / "out" / "frame_0001.exr");
  r = runCli("eval --reference " + ref + " --result " + out);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.output, "frame 1 is missing")) << r.output;
  fs::remove_all(dir);
}

TEST(CliConventions, UnknownOrMeaninglessOptionsAreUsageErrors) {
  const fs::path dir = rtd::test::scratchDir("rtd_cliconv", "usage");
  writeScene(dir, 4);
  const std::string io = " -i " + (dir / "input").string() + " -r " + (dir / "reference").string() + " -o " +
                         (dir / "cmp").string() + " --flip none";
  struct Case {
    std::string args, mentions;
  };
  const std::vector<Case> cases = {
      {"compare" + io + " --set nope=1", "nope"},
      {"compare" + io + " --methods svgf:nope=1", "nope"},
      {"compare" + io + " --methods nomethod", "nomethod"},
      {"compare" + io + " --device 0", "--device"},
      {"compare" + io + " --crop 20,0,10,10", "--crop"},
      {"compare" + io + " --frame 4", "--frame"},
      {"compare" + io + " --frames 9", "--frames"},
      {"compare" + io + " --warmup 4", "--warmup"},
      {"compare" + io + " --methods svgf,svgf", "twice"},
      {"compare" + io + " --nope", "--nope"},
      {"bench --frames 0", "--frames"},
      {"bench --size 10", "--size"},
      {"denoise -m nomethod -i " + (dir / "input").string() + " -o " + (dir / "d").string(), "nomethod"},
      {"denoise -m svgf --set variant=nope -i " + (dir / "input").string() + " -o " + (dir / "d").string(), "variant"},
      {"denoise -m accumulate --exposure 1 -i " + (dir / "input").string() + " -o " + (dir / "d").string(), "--preview"},
      {"render --scene cornell --output " + (dir / "r").string() + " --eye-distance 0.1", "--stereo"},
  };
  for (const auto& c : cases) {
    const auto r = runCli(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, c.mentions)) << c.args << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "cmp"));  // nothing was written by the refused runs
  // Bad input (a missing directory) is exit code 1, not a usage error.
  EXPECT_EQ(runCli("denoise -i " + (dir / "nope").string() + " -o " + (dir / "d").string()).code, 1);
  fs::remove_all(dir);
}

TEST(CliConventions, CompareRunsConfigurationsOfOneMethodAsLabelledRuns) {
  const fs::path dir = rtd::test::scratchDir("rtd_cliconv", "configs");
  writeScene(dir, 3);
  const auto r = runCli("compare -i " + (dir / "input").string() + " -r " + (dir / "reference").string() + " -o " +
                        (dir / "cmp").string() +
                        " --flip none --warmup 1 --methods svgf,svgf:variant=dundr:sigmaNormal=32 -m bmfr:blockSize=64");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = rtd::test::readJson(dir / "cmp" / "metrics.json");
  ASSERT_EQ(j["runs"].size(), 4u);  // the input and three configurations
  EXPECT_EQ(j["runs"][1]["label"], "svgf");
  EXPECT_EQ(j["runs"][2]["label"], "svgf variant=dundr sigmaNormal=32");
  EXPECT_EQ(j["runs"][3]["label"], "bmfr blockSize=64");
  EXPECT_EQ(j["runs"][1]["settings"]["variant"], "schied");
  EXPECT_EQ(j["runs"][2]["settings"]["variant"], "dundr");
  EXPECT_EQ(j["runs"][2]["settings"]["sigmaNormal"], "32");   // given with the preset, kept
  EXPECT_EQ(j["runs"][3]["settings"]["blockSize"], "64");
  // The two SVGF configurations really differ.
  EXPECT_NE(j["runs"][1]["steady"]["relMse"], j["runs"][2]["steady"]["relMse"]);
  std::ifstream html(dir / "cmp" / "report.html");
  const std::string page((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(contains(page, "svgf variant=dundr sigmaNormal=32"));
  fs::remove_all(dir);
}

TEST(CliConventions, ManPageHasEverySubcommandAndTheExitStatus) {
#ifndef RTD_MANPAGE
  GTEST_SKIP() << "no man page in this build (help2man not installed)";
#else
  std::ifstream in(RTD_MANPAGE);
  ASSERT_TRUE(in) << RTD_MANPAGE;
  const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(contains(page, ".SH \"EXIT STATUS\"") || contains(page, ".SH EXIT STATUS")) << page.substr(0, 400);
  for (const char* sub : {"denoise", "methods", "bench", "eval", "compare", "demo", "pack", "devices"})
    EXPECT_TRUE(contains(page, std::string(".SS ") + sub)) << sub;
  EXPECT_TRUE(contains(page, "\\-\\-overwrite") || contains(page, "--overwrite"));
#endif
}
