// rtd::applySettings: several settings by name, presets first.
#include <algorithm>

#include "rtd/denoiser.h"
#include "rtd/stereo.h"

namespace rtd {

namespace {
// Denoiser and StereoDenoiser have the same settings interface.
template <class D> void applyAssignments(D& denoiser, const std::vector<SettingAssignment>& assignments) {
  const auto known = denoiser.settings();
  const auto info = [&](const std::string& name) -> const SettingInfo* {
    const auto it = std::find_if(known.begin(), known.end(), [&](const SettingInfo& s) { return s.name == name; });
    return it == known.end() ? nullptr : &*it;
  };
  std::vector<SettingAssignment> presets, others;
  for (size_t i = 0; i < assignments.size(); ++i) {
    const auto& [name, value] = assignments[i];
    const SettingInfo* s = info(name);
    if (!s)
      throw Error("method '" + std::string(denoiser.method()) + "' has no setting '" + name +
                  "' (see `rtdenoise methods " + std::string(denoiser.method()) + "`)");
    for (size_t j = 0; j < i; ++j)
      if (assignments[j].first == name)
        throw Error("setting '" + name + "' is given twice ('" + assignments[j].second + "' and '" + value + "')");
    (s->preset ? presets : others).push_back(assignments[i]);
  }
  for (const auto& [name, value] : presets) denoiser.set(name, value);
  for (const auto& [name, value] : others) denoiser.set(name, value);
}
}  // namespace

void applySettings(Denoiser& denoiser, const std::vector<SettingAssignment>& assignments) {
  applyAssignments(denoiser, assignments);
}
void applySettings(StereoDenoiser& denoiser, const std::vector<SettingAssignment>& assignments) {
  applyAssignments(denoiser, assignments);
}

}  // namespace rtd
