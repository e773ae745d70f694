#ifdef HAVE_RTDENOISE_EVAL
#include "compare_common.h"

#include <cstdio>

namespace rtd::cli {

namespace fs = std::filesystem;

const std::vector<std::string> kComparisonOutputs = {R"(report\.html)", R"(metrics\.json)", "scene"};

void addConfigurationOptions(CLI::App* cmd, std::vector<std::string>& methods, std::vector<std::string>& settings) {
  cmd->add_option("--methods,-m", methods,
                  "configurations to run, comma-separated or repeated: method[@backend][:key=value]..., e.g. "
                  "svgf,svgf:variant=dundr,bmfr:blockSize=64,svgf@vulkan (default: every CPU method)")
      ->delimiter(',');
  cmd->add_option("--set,-s", settings,
                  "setting for every run whose method has it: key=value, or method.key=value (repeatable; a "
                  "configuration's own settings override it)");
}

eval::CompareSettings compareSettings(const std::vector<std::string>& methods, const std::vector<std::string>& settings,
                                      const DeviceOptions& device) {
  eval::CompareSettings cs;
  cs.backends = device.backends();
  cs.vulkanDevice = device.vulkanDevice;
  cs.threads = device.threads;
  cs.settings = settings;
  try {
    for (const auto& m : methods) cs.configs.push_back(eval::parseRunConfig(m));
  } catch (const Error& e) {
    throw UsageError(std::string("--methods: ") + e.what());
  }
  // Names are checked here (usage errors) rather than when the comparison starts (bad input).
  try {
    eval::checkCompareSettings(cs);
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
  return cs;
}

int shownFrameIndex(int frame, int frameCount) {
  if (frame < -1 || frame >= frameCount)
    throw UsageError("--frame " + std::to_string(frame) + ": expected -1 (the last) or an index in 0.." +
                     std::to_string(frameCount - 1));
  return frame;
}

void parseCrop(const std::string& text, int width, int height, eval::CompareSettings& cs) {
  int x = 0, y = 0, w = 0, h = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%d,%d,%d,%d%c", &x, &y, &w, &h, &extra) != 4 || w <= 0 || h <= 0)
    throw UsageError("--crop '" + text + "': expected X,Y,WIDTH,HEIGHT with WIDTH, HEIGHT >= 1");
  if (width > 0 && (x < 0 || y < 0 || x + w > width || y + h > height))
    throw UsageError("--crop '" + text + "': the crop must lie inside the " + std::to_string(width) + "x" +
                     std::to_string(height) + " image");
  cs.cropX = x, cs.cropY = y, cs.cropWidth = w, cs.cropHeight = h;
}

eval::Comparison runComparisonWithProgress(const eval::FrameSource& source, const eval::CompareSettings& cs,
                                           const std::string& what) {
  Progress progress(what, source.frameCount);
  auto c = eval::runComparison(source, cs, [&](int done, int, const std::string& detail) { progress.update(done, detail); });
  progress.finish();
  return c;
}

void writeComparison(const eval::Comparison& c, const fs::path& outDir, const std::string& json) {
  fs::create_directories(outDir);
  const fs::path jsonPath = json.empty() ? outDir / "metrics.json" : fs::path(json);
  eval::writeHtmlReport(c, outDir / "report.html");
  writeFileAtomic(jsonPath, eval::comparisonJson(c));
  std::printf("%s", eval::comparisonTable(c).c_str());
  std::printf("report: %s\nmetrics: %s\n", fs::absolute(outDir / "report.html").string().c_str(),
              fs::absolute(jsonPath).string().c_str());
}

}  // namespace rtd::cli
#endif
