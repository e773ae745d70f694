#include "eval/report_plots.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rtd::eval::report {

std::string esc(const std::string& s) {
  std::string o;
  for (char ch : s) {
    switch (ch) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&#39;"; break;
      default: o += ch;
    }
  }
  return o;
}

std::string fmt(double v, const char* f) {
  if (std::isnan(v)) return "&ndash;";
  if (std::isinf(v)) return v > 0 ? "&infin;" : "-&infin;";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

const char* runColour(size_t k) {
  static const char* kPalette[] = {"#888888", "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                   "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#393b79", "#637939"};
  return kPalette[k % (sizeof kPalette / sizeof *kPalette)];
}

Ticks niceTicks(double lo, double hi, int target) {
  Ticks t;
  if (!(hi > lo)) {
    const double pad = std::max(std::abs(hi) * 0.05, 1e-6);
    lo -= pad;
    hi += pad;
  }
  const double raw = (hi - lo) / std::max(1, target);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  const double m = raw / p;
  const double step = (m < 1.5 ? 1 : m < 3 ? 2 : m < 7 ? 5 : 10) * p;
  t.lo = std::floor(lo / step) * step;
  t.hi = std::ceil(hi / step) * step;
  for (double v = t.lo; v <= t.hi + step * 0.5; v += step) t.values.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  t.decimals = std::max(0, int(-std::floor(std::log10(step) + 1e-9)));
  return t;
}

Ticks logTicks(double lo, double hi) {
  Ticks t;
  const int d0 = int(std::floor(std::log10(lo))), d1 = int(std::ceil(std::log10(hi)));
  t.lo = std::pow(10.0, d0);
  t.hi = std::pow(10.0, std::max(d1, d0 + 1));
  const bool fine = d1 - d0 < 3;
  for (int d = d0; d <= std::max(d1, d0 + 1); ++d) {
    const double p = std::pow(10.0, d);
    t.values.push_back(p);
    if (fine && d < std::max(d1, d0 + 1))
      for (double f : {2.0, 5.0})
        if (f * p >= lo * 0.999 && f * p <= hi * 1.001) t.values.push_back(f * p);
  }
  std::sort(t.values.begin(), t.values.end());
  t.decimals = std::max(0, -d0);
  return t;
}

bool wantsLogAxis(double lo, double hi) { return lo > 0 && hi / lo > 20.0; }

namespace {
std::string tickLabel(double v, const Ticks& t, bool log) {
  char buf[32];
  if (log && (v < 1e-3 || v >= 1e4)) std::snprintf(buf, sizeof buf, "%.0e", v);
  else if (log) std::snprintf(buf, sizeof buf, "%.*f", std::max(0, int(-std::floor(std::log10(v) + 1e-9))), v);
  else std::snprintf(buf, sizeof buf, "%.*f", std::min(t.decimals, 6), v);
  return buf;
}
}  // namespace

std::string legend(const Comparison& c) {
  std::ostringstream s;
  s << "<div class='legend'>";
  for (size_t k = 0; k < c.runs.size(); ++k) s << "<span><i style='background:" << runColour(k) << "'></i>" << esc(c.runs[k].label) << "</span>";
  s << "</div>\n";
  return s.str();
}

std::string metricPlot(const Comparison& c, const MetricInfo& m) {
  const double W = 640, H = 250, left = 62, right = 14, top = 30, bottom = 34;
  double lo = INFINITY, hi = -INFINITY;
  int fmin = INT32_MAX, fmax = INT32_MIN;
  for (const auto& r : c.runs)
    for (const auto& f : r.metrics.frames) {
      fmin = std::min(fmin, f.number);
      fmax = std::max(fmax, f.number);
      const double v = f.*m.field;
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  std::ostringstream s;
  const double pw = W - left - right, ph = H - top - bottom;
  s << "<svg xmlns='http://www.w3.org/2000/svg' class='plot' viewBox='0 0 " << W << ' ' << H << "' role='img' aria-label='"
    << esc(m.label) << " per frame' data-f0='" << fmin << "' data-f1='" << fmax << "' data-x0='" << left << "' data-x1='"
    << left + pw << "'>";
  s << "<text x='" << left << "' y='16' class='pt'>" << esc(m.label) << " (" << esc(m.space) << "; "
    << (!m.ranked ? "information, not ranked" : m.higherIsBetter ? "higher is better" : "lower is better") << ")</text>";
  if (!(lo <= hi) || fmin > fmax) {
    s << "<text x='" << left << "' y='" << H / 2 << "' class='tk'>no values</text></svg>";
    return s.str();
  }
  const bool log = wantsLogAxis(lo, hi);
  const Ticks ticks = log ? logTicks(lo, hi) : niceTicks(lo, hi);
  const auto X = [&](double f) { return left + (fmax > fmin ? (f - fmin) / double(fmax - fmin) : 0.5) * pw; };
  const auto Y = [&](double v) {
    const double t = log ? (std::log10(v) - std::log10(ticks.lo)) / (std::log10(ticks.hi) - std::log10(ticks.lo))
                         : (v - ticks.lo) / (ticks.hi - ticks.lo);
    return top + (1.0 - t) * ph;
  };
  // Warm-up region.
  int lastWarm = INT32_MIN;
  for (const auto& f : c.runs.front().metrics.frames)
    if (f.warmup) lastWarm = std::max(lastWarm, f.number);
  if (lastWarm != INT32_MIN)
    s << "<rect x='" << left << "' y='" << top << "' width='" << std::max(0.0, std::min(X(lastWarm + 0.5), left + pw) - left)
      << "' height='" << ph << "' fill='#f1ead9'/><text x='" << left + 4 << "' y='" << top + 12 << "' class='wl'>warm-up</text>";
  s << "<rect x='" << left << "' y='" << top << "' width='" << pw << "' height='" << ph << "' fill='none' stroke='#999'/>";
  for (double v : ticks.values) {
    const double y = Y(v);
    s << "<line x1='" << left << "' x2='" << left + pw << "' y1='" << y << "' y2='" << y << "' stroke='#e4e4e4'/>"
      << "<text x='" << left - 6 << "' y='" << y + 4 << "' text-anchor='end' class='tk'>" << tickLabel(v, ticks, log) << "</text>";
  }
  if (log) s << "<text x='" << left + pw - 4 << "' y='" << top + 12 << "' text-anchor='end' class='tk'>log scale</text>";
  const Ticks ft = niceTicks(fmin, std::max(fmax, fmin + 1), std::min(8, std::max(1, fmax - fmin)));
  for (double f : ft.values) {
    if (f < fmin || f > fmax || f != std::floor(f)) continue;
    s << "<text x='" << X(f) << "' y='" << top + ph + 16 << "' text-anchor='middle' class='tk'>" << int(f) << "</text>";
  }
  s << "<text x='" << left + pw / 2 << "' y='" << H - 3 << "' text-anchor='middle' class='tk'>frame</text>";
  for (size_t k = 0; k < c.runs.size(); ++k) {
    const auto& r = c.runs[k];
    std::ostringstream pts, dots;
    for (const auto& f : r.metrics.frames) {
      const double v = f.*m.field;
      if (!std::isfinite(v)) continue;
      pts << X(f.number) << ',' << Y(v) << ' ';
      dots << "<circle cx='" << X(f.number) << "' cy='" << Y(v) << "' r='2.6' fill='" << runColour(k) << "' data-f='"
           << f.number << "'><title>" << esc(r.label) << ", frame " << f.number << ": " << formatMetric(m, v)
           << "</title></circle>";
    }
    s << "<polyline fill='none' stroke='" << runColour(k) << "' stroke-width='1.6' points='" << pts.str() << "'/>" << dots.str();
  }
  s << "<line class='cur' x1='" << left << "' x2='" << left << "' y1='" << top << "' y2='" << top + ph << "'/>";
  s << "</svg>";
  return s.str();
}

std::vector<std::string> passNames(const Comparison& c) {
  std::vector<std::string> passes;
  for (const auto& r : c.runs)
    for (const auto& p : r.passOrder)
      if (std::find(passes.begin(), passes.end(), p) == passes.end()) passes.push_back(p);
  return passes;
}

std::string timingBars(const Comparison& c) {
  std::vector<const MethodRun*> runs;
  for (const auto& r : c.runs)
    if (!r.method.empty()) runs.push_back(&r);
  if (runs.empty()) return "";
  const auto passes = passNames(c);
  // A pass colour per name, the same in every bar.
  static const char* kPassColours[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1",
                                       "#ff9da7", "#9c755f", "#bab0ac", "#86bcb6", "#d37295", "#a0cbe8", "#ffbe7d"};
  const auto colour = [&](size_t i) { return kPassColours[i % (sizeof kPassColours / sizeof *kPassColours)]; };
  double maxTotal = 0;
  for (const auto* r : runs) {
    double sum = 0;
    for (const auto& p : r->passOrder) sum += std::isfinite(r->medianPassMs(p)) ? r->medianPassMs(p) : 0;
    maxTotal = std::max({maxTotal, sum, std::isfinite(r->medianTotalMs()) ? r->medianTotalMs() : 0.0});
  }
  const Ticks t = niceTicks(0, std::max(maxTotal, 1e-3), 6);
  size_t labelChars = 0;
  for (const auto* r : runs) labelChars = std::max(labelChars, r->label.size());
  const double W = 1000, left = std::min(420.0, 12 + 6.6 * double(labelChars)), right = 90, barH = 20, gap = 8, top = 8;
  const double H = top + runs.size() * (barH + gap) + 26, pw = W - left - right;
  const auto X = [&](double ms) { return left + ms / t.hi * pw; };
  std::ostringstream s;
  s << "<div class='legend'>";
  for (size_t i = 0; i < passes.size(); ++i) s << "<span><i style='background:" << colour(i) << "'></i>" << esc(passes[i]) << "</span>";
  s << "</div><svg xmlns='http://www.w3.org/2000/svg' class='bars' viewBox='0 0 " << W << ' ' << H
    << "' role='img' aria-label='per-pass timing'>";
  for (double v : t.values) {
    s << "<line x1='" << X(v) << "' x2='" << X(v) << "' y1='" << top << "' y2='" << H - 22 << "' stroke='#e4e4e4'/>"
      << "<text x='" << X(v) << "' y='" << H - 8 << "' text-anchor='middle' class='tk'>" << fmt(v, ("%." + std::to_string(t.decimals) + "f").c_str())
      << "</text>";
  }
  s << "<text x='" << W - 4 << "' y='" << H - 8 << "' text-anchor='end' class='tk'>ms</text>";
  for (size_t k = 0; k < runs.size(); ++k) {
    const auto* r = runs[k];
    const double y = top + k * (barH + gap);
    s << "<text x='" << left - 8 << "' y='" << y + barH * 0.7 << "' text-anchor='end' class='tk'>" << esc(r->label) << "</text>";
    double at = 0;
    for (const auto& p : r->passOrder) {
      const double ms = r->medianPassMs(p);
      if (!std::isfinite(ms) || ms <= 0) continue;
      const size_t ci = size_t(std::find(passes.begin(), passes.end(), p) - passes.begin());
      s << "<rect x='" << X(at) << "' y='" << y << "' width='" << std::max(0.5, X(at + ms) - X(at)) << "' height='" << barH
        << "' fill='" << colour(ci) << "'><title>" << esc(r->label) << ": " << esc(p) << " " << fmt(ms, "%.3f")
        << " ms (median)</title></rect>";
      at += ms;
    }
    s << "<text x='" << X(at) + 6 << "' y='" << y + barH * 0.7 << "' class='tk'>" << fmt(r->medianTotalMs(), "%.2f") << " ms</text>";
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace rtd::eval::report
