// rtdenoise — settings: every method has a typed struct (include/rtd/methods/*.h) whose fields
// carry the papers' defaults. The same fields can be listed and set by name (CLI `--set k=v`).
#pragma once
#include <string>
#include <vector>

namespace rtd {

/// Description of one setting of a method, as `rtdenoise methods` prints it.
struct SettingInfo {
  std::string name;                  ///< e.g. "sigmaLuminance"
  std::string type;                  ///< "float", "int", "bool", "enum" or "string" (a file path)
  std::string value;                 ///< current value, as text
  std::string doc;                   ///< meaning and source of the default
  std::vector<std::string> choices;  ///< allowed values of an enum
  /// A preset: setting it by name resets other settings (SVGF's "variant"). setSettings()
  /// applies presets before the other settings given with them.
  bool preset = false;
};

/// Description of a registered method.
struct MethodInfo {
  std::string name;     ///< "accumulate", "svgf", ...
  std::string summary;  ///< one line
  std::vector<SettingInfo> settings;  ///< with their defaults
  bool cpu = false;     ///< available on Backend::Cpu
  bool vulkan = false;  ///< available on Backend::Vulkan
};

}  // namespace rtd
