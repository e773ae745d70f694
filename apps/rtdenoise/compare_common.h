// What `rtdenoise compare` and `demo` share: the configuration options, checks of the shown
// frame and crop, running with a progress bar and writing the report.
#pragma once
#ifdef HAVE_RTDENOISE_EVAL
#include <filesystem>
#include <string>
#include <vector>

#include "cli.h"
#include "rtd/eval/compare.h"

namespace rtd::cli {

/// What compare and demo write into their output directory (and --overwrite replaces).
extern const std::vector<std::string> kComparisonOutputs;

/// `--methods` (configurations, repeatable, comma-separated) and `--set`.
void addConfigurationOptions(CLI::App* cmd, std::vector<std::string>& methods, std::vector<std::string>& settings);

/// The configurations (`--methods`), global settings (`--set`) and backends as
/// CompareSettings, with every method and setting name checked (UsageError naming the option).
eval::CompareSettings compareSettings(const std::vector<std::string>& methods, const std::vector<std::string>& settings,
                                      const DeviceOptions& device);

/// `--frame I` (-1 = last) checked against the frame count.
int shownFrameIndex(int frame, int frameCount);
/// `--crop X,Y,W,H` parsed and checked against the image size (when known, > 0).
void parseCrop(const std::string& text, int width, int height, eval::CompareSettings& cs);

eval::Comparison runComparisonWithProgress(const eval::FrameSource& source, const eval::CompareSettings& cs,
                                           const std::string& what);
/// Writes <outDir>/report.html and the metrics JSON (`json`, default <outDir>/metrics.json);
/// prints the table and both paths.
void writeComparison(const eval::Comparison& c, const std::filesystem::path& outDir, const std::string& json);

}  // namespace rtd::cli
#endif
