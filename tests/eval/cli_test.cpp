// The eval/compare/demo commands end to end on a tiny scene, and their error messages.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rtd/rtd.h"
#include "support/run_cli.h"
#include "support/files.h"

namespace fs = std::filesystem;

namespace {
using rtd::test::runCli;
}  // namespace

TEST(EvalCli, DemoDenoiseEvalAndCompare) {
  const fs::path dir = fs::temp_directory_path() / ("rtd_cli_eval_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto demo = runCli("demo --output " + (dir / "demo").string() + " --scene synthetic --size 48x32 --frames 4 --warmup 1 --save-scene");
  ASSERT_EQ(demo.code, 0) << demo.output;
  EXPECT_NE(demo.output.find("report: "), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "demo" / "report.html"));
  const auto demoJson = rtd::test::readJson(dir / "demo" / "metrics.json");
  EXPECT_EQ(demoJson["frames"], 4);

  const fs::path scene = dir / "demo" / "scene";
  const auto den = runCli("denoise -m accumulate -i " + (scene / "input").string() + " -o " + (dir / "out").string());
  ASSERT_EQ(den.code, 0) << den.output;
  const auto ev = runCli("eval --reference " + (scene / "reference").string() + " --result " + (dir / "out").string() +
                         " --input " + (scene / "input").string() + " --warmup 1 --json " + (dir / "eval.json").string());
  ASSERT_EQ(ev.code, 0) << ev.output;
  EXPECT_NE(ev.output.find("PSNR"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "out" / "metrics.json"));  // nothing written into the result folder
  const auto j = rtd::test::readJson(dir / "eval.json");
  ASSERT_EQ(j["streams"].size(), 2u);
  EXPECT_EQ(j["streams"][0]["frames"].size(), 4u);
  // The denoised result is closer to the reference than the input; numbers agree with the demo's.
  EXPECT_LT(j["streams"][0]["steady"]["relMse"].get<double>(), j["streams"][1]["steady"]["relMse"].get<double>());
  EXPECT_NEAR(j["streams"][0]["steady"]["psnr"].get<double>(), demoJson["runs"][1]["steady"]["psnr"].get<double>(), 1e-3);

  const auto cmp = runCli("compare -i " + (scene / "input").string() + " -r " + (scene / "reference").string() +
                          " -o " + (dir / "cmp").string() + " --warmup 1 --flip none");
  ASSERT_EQ(cmp.code, 0) << cmp.output;
  EXPECT_TRUE(fs::exists(dir / "cmp" / "report.html"));

  // Bad inputs: a missing reference frame and a size mismatch name the file.
  fs::remove(scene / "reference" / "frame_0003.exr");
  auto bad = runCli("eval --reference " + (scene / "reference").string() + " --result " + (dir / "out").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.output.find("frame_0003.exr"), std::string::npos) << bad.output;
  rtd::writeRgbExr(scene / "reference" / "frame_0003.exr", rtd::Image(20, 10, 3));
  bad = runCli("eval --reference " + (scene / "reference").string() + " --result " + (dir / "out").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.output.find("frame_0003.exr"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("20x10"), std::string::npos) << bad.output;
  fs::remove_all(dir);
}
