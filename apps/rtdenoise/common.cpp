#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>

#include "cli.h"

namespace rtd::cli {

namespace fs = std::filesystem;

const char* const kExitStatusFooter =
    "Exit status: 0 success; 1 bad input data or files (the message names the file, frame and channel); "
    "2 usage error (unknown or meaningless option, bad value); 3 internal error. See docs/cli.md.\n";

CLI::App* addSubcommand(CLI::App& app, const std::string& name, const std::string& description) {
  CLI::App* cmd = app.add_subcommand(name, description);
  cmd->footer(kExitStatusFooter);
  return cmd;
}

std::vector<SettingAssignment> parseAssignments(const std::vector<std::string>& texts, const std::string& option) {
  std::vector<SettingAssignment> out;
  for (const auto& a : texts) {
    const auto eq = a.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError(option + " '" + a + "': expected key=value");
    out.emplace_back(a.substr(0, eq), a.substr(eq + 1));
  }
  return out;
}

namespace {
template <class D> void applySetTexts(D& d, const std::vector<std::string>& assignments) {
  try {
    rtd::applySettings(d, parseAssignments(assignments));
  } catch (const Error& e) {
    throw UsageError(std::string("--set: ") + e.what());
  }
}
}  // namespace

void applySettings(Denoiser& d, const std::vector<std::string>& assignments) { applySetTexts(d, assignments); }
void applySettings(StereoDenoiser& d, const std::vector<std::string>& assignments) { applySetTexts(d, assignments); }

CLI::Validator atLeast(double lo) {
  return CLI::Validator(
      [lo](std::string& text) -> std::string {
        double v = 0;
        char extra = 0;
        if (std::sscanf(text.c_str(), "%lf%c", &v, &extra) != 1) return "'" + text + "' is not a number";
        std::ostringstream s;
        s << lo;
        return v >= lo ? std::string() : "must be >= " + s.str() + " (got " + text + ")";
      },
      "");
}

MethodInfo methodInfo(const std::string& name, const std::string& option) {
  std::string names;
  for (const auto& m : listMethods()) {
    if (m.name == name) return m;
    names += (names.empty() ? "" : ", ") + m.name;
  }
  throw UsageError(option + " '" + name + "': no such method (methods: " + names + ")");
}

std::pair<int, int> parseSize(const std::string& s, const std::string& option) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w <= 0 || h <= 0 ||
      w > 16384 || h > 16384)
    throw UsageError(option + " '" + s + "': expected WIDTHxHEIGHT between 1x1 and 16384x16384, e.g. 1280x720");
  return {w, h};
}

Backend parseBackend(const std::string& s) {
  if (s == "cpu") return Backend::Cpu;
  if (s == "vulkan") return Backend::Vulkan;
  throw UsageError("--backend '" + s + "': expected cpu or vulkan");
}

std::vector<std::string> splitList(const std::string& s, char separator) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, separator))
    if (!item.empty()) out.push_back(item);
  return out;
}

void DeviceOptions::add(CLI::App* cmd, bool list) {
  cmd->add_option("--backend,-b", backend, list ? "comma-separated backends: cpu, vulkan" : "cpu or vulkan")
      ->capture_default_str();
  cmd->add_option("--device", vulkanDevice, "Vulkan device index or name substring (see `rtdenoise devices`); "
                                            "only with --backend vulkan");
  cmd->add_option("--threads", threads, "CPU threads (0 = all cores)")->capture_default_str()->check(atLeast(0));
}

std::vector<Backend> DeviceOptions::backends() const {
  std::vector<Backend> out;
  for (const auto& b : splitList(backend)) {
    const Backend parsed = parseBackend(b);
    if (std::find(out.begin(), out.end(), parsed) != out.end()) throw UsageError("--backend '" + backend + "': '" + b + "' is listed twice");
    out.push_back(parsed);
  }
  if (out.empty()) throw UsageError("--backend: give cpu or vulkan");
  if (!vulkanDevice.empty() && std::find(out.begin(), out.end(), Backend::Vulkan) == out.end())
    throw UsageError("--device '" + vulkanDevice + "' selects a Vulkan device, but --backend is '" + backend +
                     "' (add --backend vulkan, or drop --device)");
  return out;
}

Backend DeviceOptions::single() const {
  const auto list = backends();
  if (list.size() > 1) throw UsageError("--backend '" + backend + "': this subcommand runs on one backend");
  return list.front();
}

void OutputOptions::add(CLI::App* cmd, const std::string& what, bool required) {
  auto* o = cmd->add_option("--output,-o", dir, "output directory: " + what);
  if (required) o->required();
  cmd->add_flag("--overwrite", overwrite,
                "replace the results of an earlier run in the output directory (refused without it)");
}

void OutputOptions::prepare(const std::vector<std::string>& ours) const {
  const fs::path path(dir);
  if (fs::exists(path) && !fs::is_directory(path)) throw UsageError("--output '" + dir + "' exists and is not a directory");
  if (!fs::exists(path)) {
    fs::create_directories(path);
    return;
  }
  removeStaleTemporaryFiles(path);  // left by a killed run; a running one's still count below
  std::vector<std::regex> patterns;
  for (const auto& p : ours) patterns.emplace_back(p);
  std::vector<fs::path> mine, foreign;
  static const std::regex temporary(R"(.+\.tmp\d+)");  // a running writer's (TemporaryFile): left alone
  for (const auto& e : fs::directory_iterator(path)) {
    const std::string name = e.path().filename().string();
    if (std::regex_match(name, temporary)) continue;
    const bool match = std::any_of(patterns.begin(), patterns.end(), [&](const std::regex& r) { return std::regex_match(name, r); });
    (match ? mine : foreign).push_back(e.path());
  }
  if (mine.empty() && foreign.empty()) return;
  const auto example = [](const std::vector<fs::path>& v) {
    std::string s;
    for (size_t i = 0; i < v.size() && i < 3; ++i) s += (i ? ", " : "") + v[i].filename().string();
    return s + (v.size() > 3 ? ", ..." : "");
  };
  if (!foreign.empty())
    throw UsageError("--output '" + dir + "' holds files this command does not write (" + example(foreign) +
                     "); choose an empty or new directory" + (overwrite ? " (--overwrite only replaces earlier results)" : ""));
  if (!overwrite)
    throw UsageError("--output '" + dir + "' already holds results of an earlier run (" + std::to_string(mine.size()) +
                     " entries: " + example(mine) + "); add --overwrite to replace them, or choose another directory");
  for (const auto& p : mine) fs::remove_all(p);
}

int framesToUse(int requested, int available, const std::string& option) {
  if (requested < 0) throw UsageError(option + " " + std::to_string(requested) + ": must be >= 0 (0 = all)");
  if (requested > available)
    throw UsageError(option + " " + std::to_string(requested) + ": the sequence has only " + std::to_string(available) +
                     " frame(s)");
  return requested > 0 ? requested : available;
}

Progress::Progress(std::string what, int total)
    : what_(std::move(what)), total_(total), tty_(::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()), lastPrint_(start_) {}

void Progress::update(int done, const std::string& detail) {
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (!tty_ && std::chrono::duration<double>(now - lastPrint_).count() < 5.0 && done != total_) return;
  lastPrint_ = now;
  const double eta = done > 0 ? elapsed / done * (total_ - done) : 0.0;
  const int width = 30, filled = total_ > 0 ? width * done / total_ : width;
  std::string bar(size_t(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "%s%s [%s] %d/%d  %.1fs elapsed, ETA %.1fs  %s%s", tty_ ? "\r\033[K" : "", what_.c_str(),
               bar.c_str(), done, total_, elapsed, eta, detail.c_str(), tty_ ? "" : "\n");
  std::fflush(stderr);
}

void Progress::finish(const std::string& detail) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "%s%s: %d/%d done in %.1fs %s\n", tty_ ? "\r\033[K" : "", what_.c_str(), total_, total_,
               elapsed, detail.c_str());
}

}  // namespace rtd::cli
