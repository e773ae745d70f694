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
  void operator()(const char* n, std::string& v, const char* doc) { out.push_back({n, "string", v, doc, {}}); }
  template <class E, class = std::enable_if_t<std::is_enum_v<E>>>
  void operator()(const char* n, E& v, const char* doc, Choices choices) {
    SettingInfo info{n, "enum", "", doc, {}};
    for (const char* c : choices) info.choices.emplace_back(c);
    size_t i = size_t(v);
    info.value = i < info.choices.size() ? info.choices[i] : std::to_string(i);
    out.push_back(std::move(info));
  }
};

/// Sets the field named `key` from text, checking only that the text is a value of the field's
/// type (a finite number, an integer, a bool, one of an enum's names); ranges are checked for
/// the whole struct afterwards by SettingValidator, the same check typed settings get.
/// Throws rtd::Error on a malformed value.
struct SettingSetter {
  std::string_view key, value;
  bool found = false;

  [[noreturn]] void fail(const char* expected) const {
    throw Error("setting '" + std::string(key) + "': cannot use '" + std::string(value) + "' (expected " + expected + ")");
  }
  void operator()(const char* n, float& v, const char*, Range = {}) {
    if (key != n) return;
    found = true;
    std::string s(value);
    char* end = nullptr;
    float parsed = std::strtof(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(parsed)) fail("a finite number");
    v = parsed;
  }
  void operator()(const char* n, int& v, const char*, Range = {}) {
    if (key != n) return;
    found = true;
    int parsed = 0;
    auto [p, ec] = std::from_chars(value.data(), value.data() + value.size(), parsed);
    if (ec != std::errc() || p != value.data() + value.size()) fail("an integer");
    v = parsed;
  }
  void operator()(const char* n, bool& v, const char*) {
    if (key != n) return;
    found = true;
    if (value == "true" || value == "1" || value == "on") v = true;
    else if (value == "false" || value == "0" || value == "off") v = false;
    else fail("true or false");
  }
  void operator()(const char* n, std::string& v, const char*) {
    if (key != n) return;
    found = true;
    v = std::string(value);
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

/// Checks every field of a settings struct against what its visit() declares: floats finite,
/// numbers within their Range, enums one of their choices. Settings given by name and typed
/// settings (Denoiser::setSettings) both pass through it before they replace the current ones.
struct SettingValidator {
  std::string_view method;

  [[noreturn]] void fail(const char* n, const std::string& what) const {
    throw Error("setting '" + std::string(n) + "' of method '" + std::string(method) + "': " + what);
  }
  void checkRange(const char* n, double v, const std::string& text, Range r) const {
    if (!(v >= r.lo && v <= r.hi)) {
      std::ostringstream s;
      s << text << " is outside [" << r.lo << ", " << r.hi << "]";
      fail(n, s.str());
    }
  }
  void operator()(const char* n, float& v, const char*, Range r = {-INFINITY, INFINITY}) {
    if (!std::isfinite(v)) fail(n, formatFloat(v) + " is not a finite number");
    checkRange(n, v, formatFloat(v), r);
  }
  void operator()(const char* n, int& v, const char*, Range r = {-2147483648.0, 2147483647.0}) {
    checkRange(n, v, std::to_string(v), r);
  }
  void operator()(const char*, bool&, const char*) {}
  void operator()(const char*, std::string&, const char*) {}  // any text (a file is checked where it is read)
  template <class E, class = std::enable_if_t<std::is_enum_v<E>>>
  void operator()(const char* n, E& v, const char*, Choices choices) {
    const auto i = static_cast<long long>(v);
    if (i < 0 || i >= static_cast<long long>(choices.size())) {
      std::string names;
      for (const char* c : choices) names += (names.empty() ? "" : ", ") + std::string(c);
      fail(n, "enum value " + std::to_string(i) + " is not one of " + names);
    }
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

/// Throws rtd::Error naming the first field of `s` that its visit() declaration refuses.
template <class S> void validateSettings(S s, std::string_view method) {
  SettingValidator v{method};
  s.visit(v);
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
    replaceSettings(copy);
  }

 protected:
  void* settingsStorage(std::string_view m) override {
    checkMethod(m);
    return &settings_;
  }
  void assignSettings(std::string_view m, const void* s) override {
    checkMethod(m);
    replaceSettings(*static_cast<const S*>(s));
  }
  S settings_;

 private:
  // The one way settings change, by name or typed: the whole struct is validated before it
  // replaces the current settings, so a refused value touches neither settings nor history.
  void replaceSettings(const S& s) {
    detail::validateSettings(s, S::kMethod);
    settings_ = s;
    this->settingsChanged();
  }
  static void checkMethod(std::string_view m) {
    if (m != S::kMethod)
      throw Error("settings of method '" + std::string(m) + "' given to a '" + std::string(S::kMethod) + "' denoiser");
  }
};

}  // namespace rtd
