// rtdenoise methods: every method with its settings and their defaults.
#include <nlohmann/json.hpp>

#include "cli.h"

namespace rtd::cli {

void addMethods(CLI::App& app) {
  auto asJson = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("methods", "list methods and their settings with defaults");
  cmd->add_flag("--json", *asJson, "print JSON");
  cmd->callback([asJson] {
    const auto methods = listMethods();
    if (*asJson) {
      nlohmann::json j = nlohmann::json::array();
      for (const auto& m : methods) {
        nlohmann::json s = nlohmann::json::array();
        for (const auto& f : m.settings)
          s.push_back({{"name", f.name}, {"type", f.type}, {"default", f.value}, {"doc", f.doc}, {"choices", f.choices}});
        j.push_back({{"name", m.name}, {"summary", m.summary}, {"cpu", m.cpu}, {"vulkan", m.vulkan}, {"settings", s}});
      }
      std::printf("%s\n", j.dump(2).c_str());
      return;
    }
    for (const auto& m : methods) {
      std::printf("%s  (%s%s)\n  %s\n", m.name.c_str(), m.cpu ? "cpu" : "", m.vulkan ? ", vulkan" : "", m.summary.c_str());
      for (const auto& f : m.settings) {
        std::string type = f.type;
        if (!f.choices.empty()) {
          type = "";
          for (const auto& c : f.choices) type += (type.empty() ? "" : "|") + c;
        }
        std::printf("    %-24s %-8s = %-10s %s\n", f.name.c_str(), type.c_str(), f.value.c_str(), f.doc.c_str());
      }
      std::printf("\n");
    }
  });
}

}  // namespace rtd::cli
