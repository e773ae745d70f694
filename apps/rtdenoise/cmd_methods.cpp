// rtdenoise methods: every method (or the named ones) with its settings and their defaults.
#include <nlohmann/json.hpp>

#include "cli.h"

namespace rtd::cli {

namespace {
struct MethodsOptions {
  std::vector<std::string> names;
  std::string json;
};

void runMethods(const MethodsOptions& o) {
  std::vector<MethodInfo> methods;
  if (o.names.empty()) methods = listMethods();
  for (const auto& n : o.names) methods.push_back(methodInfo(n, "methods"));
  if (!o.json.empty()) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& m : methods) {
      nlohmann::json s = nlohmann::json::array();
      for (const auto& f : m.settings)
        s.push_back({{"name", f.name}, {"type", f.type}, {"default", f.value}, {"doc", f.doc}, {"choices", f.choices},
                     {"preset", f.preset}});
      j.push_back({{"name", m.name}, {"summary", m.summary}, {"cpu", m.cpu}, {"vulkan", m.vulkan}, {"settings", s}});
    }
    if (o.json == "-") std::printf("%s\n", j.dump(2).c_str());
    else writeFileAtomic(o.json, j.dump(2) + "\n");
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
}
}  // namespace

void addMethods(CLI::App& app) {
  auto o = std::make_shared<MethodsOptions>();
  auto* cmd = addSubcommand(app, "methods", "list methods (all, or the named ones) and their settings with defaults");
  cmd->add_option("names", o->names, "method names (default: every method)");
  cmd->add_option("--json", o->json, "FILE: write the list as JSON to FILE ('-' for standard output)");
  cmd->callback([o] { runMethods(*o); });
}

}  // namespace rtd::cli
