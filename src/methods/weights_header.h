// The header every learned method's weights file shares (docs/methods/tnnd.md, rae.md): JSON
// with the method's "format" string, the "version" this library reads, and the fixed choices
// of the model (colour transform, normal space, ...) as string fields. Each failure throws an
// rtd::Error naming the file and the field.
#pragma once
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "rtd/error.h"

namespace rtd {

/// Parses `text` (from `source`) and checks its header; `method` names the model in messages
/// ("TNND"). `fixed`: (field, required value) pairs.
inline nlohmann::json parseWeightsHeader(const std::string& text, const std::string& source, const char* method,
                                         const char* format, int version,
                                         std::initializer_list<std::pair<const char*, const char*>> fixed) {
  auto fail = [&](const std::string& what) { throw Error(std::string(method) + " weights '" + source + "': " + what); };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    fail(std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("format", "") != format) fail(std::string("field 'format' must be \"") + format + "\"");
  if (!j.contains("version") || !j["version"].is_number_integer() || j["version"].get<int>() != version)
    fail("field 'version' must be " + std::to_string(version) + " (the version this library reads)");
  for (const auto& [field, value] : fixed)
    if (j.value(field, "") != value) fail(std::string("field '") + field + "' must be \"" + value + "\"");
  return j;
}

}  // namespace rtd
