// The report's SVG pieces: per-frame metric plots (rounded ticks, a log axis where values span
// decades, hover values) and stacked per-pass timing bars (internal to librtdenoise_eval).
#pragma once
#include <string>
#include <vector>

#include "rtd/eval/compare.h"

namespace rtd::eval::report {

std::string esc(const std::string& s);
/// printf-formatted number; "&ndash;" for NaN, "&infin;" for infinity.
std::string fmt(double v, const char* format = "%.4g");

/// The colour of run k (the input grey, then a fixed palette).
const char* runColour(size_t k);

/// Ticks of an axis: "nice" values (1, 2 or 5 times a power of ten) covering [lo, hi].
struct Ticks {
  double lo = 0, hi = 1;        ///< the axis range, widened to whole ticks
  std::vector<double> values;   ///< tick positions
  int decimals = 0;             ///< digits after the point that tell the ticks apart
};
Ticks niceTicks(double lo, double hi, int target = 5);
/// Decades of a log axis over [lo, hi] (lo > 0): powers of ten, with 2 and 5 between them when
/// the range spans fewer than three decades.
Ticks logTicks(double lo, double hi);
/// Whether a metric's values should be plotted on a log axis: all positive, spanning > 20x.
bool wantsLogAxis(double lo, double hi);

/// The legend of the runs' colours (HTML).
std::string legend(const Comparison& c);
/// One plot of a metric over the frames: a polyline per run, warm-up shaded, each point a
/// hover target (its <title>) that also selects the frame in the player.
std::string metricPlot(const Comparison& c, const MetricInfo& m);
/// Every pass name of every run, in first-seen order.
std::vector<std::string> passNames(const Comparison& c);
/// One horizontal bar per configuration: its passes' medians stacked, with a pass legend.
std::string timingBars(const Comparison& c);

}  // namespace rtd::eval::report
