// JSON pieces shared by `rtdenoise eval` output and the comparison report (internal).
#pragma once
#include <nlohmann/json.hpp>

#include "rtd/eval/evaluate.h"

namespace rtd::eval {
nlohmann::json summaryJson(const MetricSummary& s);
nlohmann::json framesJson(const std::vector<FrameMetrics>& frames);
nlohmann::json settingsJson(const EvalSettings& s);
}  // namespace rtd::eval
