// Listing and setting the fields of a settings struct by name, through its visit().
#pragma once
#include <charconv>
#include <cmath>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>

#include "rtd/error.h"
#include "rtd/settings.h"
#include "rtd/settings_visit.h"

namespace rtd::detail {

inline std::string formatFloat(float v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// Collects SettingInfo for every field.
struct SettingLister {
  std::vector<SettingInfo> out;
  void operator()(const char* n, float& v, const char* doc, Range = {}) { out.push_back({n, "float", formatFloat(v), doc, {}}); }
  void operator()(const char* n, int& v, const char* doc, Range = {}) { out.push_back({n, "int", std::to_string(v), doc, {}}); }
  void operator()(const char* n, bool& v, const char* doc) { out.push_back({n, "bool", v ? "true" : "false", doc, {}}); }
  template <class E, class = std::enable_if_t<std::is_enum_v<E>>>
  void operator()(const char* n, E& v, const char* doc, Choices choices) {
    SettingInfo info{n, "enum", "", doc, {}};
    for (const char* c : choices) info.choices.emplace_back(c);
    size_t i = size_t(v);
    info.value = i < info.choices.size() ? info.choices[i] : std::to_string(i);
    out.push_back(std::move(info));
  }
};

/// Sets the field named `key` from text; throws rtd::Error on a bad value.
struct SettingSetter {
  std::string_view key, value;
  bool found = false;

  [[noreturn]] void fail(const char* expected) const {
    throw Error("setting '" + std::string(key) + "': cannot use '" + std::string(value) + "' (expected " + expected + ")");
  }
  void checkRange(double v, Range r) const {
    if (!(v >= r.lo && v <= r.hi)) {
      std::ostringstream s;
      s << "setting '" << key << "': " << value << " is outside [" << r.lo << ", " << r.hi << "]";
      throw Error(s.str());
    }
  }
  void operator()(const char* n, float& v, const char*, Range r = {-INFINITY, INFINITY}) {
    if (key != n) return;
    found = true;
    std::string s(value);
    char* end = nullptr;
    float parsed = std::strtof(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(parsed)) fail("a finite number");
    checkRange(parsed, r);
    v = parsed;
  }
  void operator()(const char* n, int& v, const char*, Range r = {-2147483648.0, 2147483647.0}) {
    if (key != n) return;
    found = true;
    int parsed = 0;
    auto [p, ec] = std::from_chars(value.data(), value.data() + value.size(), parsed);
    if (ec != std::errc() || p != value.data() + value.size()) fail("an integer");
    checkRange(parsed, r);
    v = parsed;
  }
  void operator()(const char* n, bool& v, const char*) {
    if (key != n) return;
    found = true;
    if (value == "true" || value == "1" || value == "on") v = true;
    else if (value == "false" || value == "0" || value == "off") v = false;
    else fail("true or false");
  }
  template <class E, class = std::enable_if_t<std::is_enum_v<E>>>
  void operator()(const char* n, E& v, const char*, Choices choices) {
    if (key != n) return;
    found = true;
    int i = 0;
    std::string names;
    for (const char* c : choices) {
      if (value == c) { v = E(i); return; }
      names += (i ? ", " : "") + std::string(c);
      ++i;
    }
    fail(("one of " + names).c_str());
  }
};

template <class S> std::vector<SettingInfo> listSettings(S s) {
  SettingLister l;
  s.visit(l);
  if constexpr (requires { S::isPreset(std::string_view()); })
    for (auto& info : l.out) info.preset = S::isPreset(info.name);
  return std::move(l.out);
}

template <class S> void setSetting(S& s, std::string_view method, std::string_view key, std::string_view value) {
  SettingSetter setter{key, value};
  s.visit(setter);
  if (!setter.found) throw Error("method '" + std::string(method) + "' has no setting '" + std::string(key) + "' (see `rtdenoise methods`)");
}

}  // namespace rtd::detail

namespace rtd {

/// Settings by name and by type for a denoiser of method S: every backend's denoiser base
/// derives from this (`Base` is rtd::Denoiser or a backend's base class).
template <class S, class Base> class TypedSettings : public Base {
 public:
  using Base::Base;
  std::string_view method() const override { return S::kMethod; }
  std::vector<SettingInfo> settings() const override { return detail::listSettings(settings_); }
  void set(std::string_view name, std::string_view value) override {
    S copy = settings_;  // a rejected value leaves the settings untouched
    detail::setSetting(copy, S::kMethod, name, value);
    // A settings struct may react to a field set by name (SVGF's "variant" is a preset).
    if constexpr (requires { copy.settingSet(name); }) copy.settingSet(name);
    settings_ = copy;
    this->settingsChanged();
  }

 protected:
  void* settingsStorage(std::string_view m) override {
    if (m != S::kMethod)
      throw Error("settings of method '" + std::string(m) + "' given to a '" + std::string(S::kMethod) + "' denoiser");
    return &settings_;
  }
  S settings_;
};

}  // namespace rtd
