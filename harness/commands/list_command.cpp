#include "harness/commands/list_command.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <ostream>

#include "estimators/registry.h"
#include "harness/session/session.h"
#include "integrands/registry.h"

namespace pcbench {
namespace {

using Json = nlohmann::ordered_json;

Json params_json(const std::vector<ParamSpec>& specs) {
  Json out = Json::array();
  for (const ParamSpec& spec : specs) {
    out.push_back(
        Json{{"name", spec.name},
             {"type", describe_type(spec)},
             {"default", spec.required || spec.optional ? Json(nullptr) : Json(spec.default_value)},
             {"required", spec.required},
             {"description", spec.description}});
  }
  return out;
}

void print_params(std::ostream& out, const std::vector<ParamSpec>& specs) {
  for (const ParamSpec& spec : specs) {
    std::string default_text = spec.required   ? "required"
                               : spec.optional ? "optional"
                                               : "default " + spec.default_value;
    out << fmt::format("      {:<12} {} ({}; {})\n", spec.name, spec.description,
                       describe_type(spec), default_text);
  }
}

Json configurations_json(const std::vector<NamedParams>& configurations) {
  Json out = Json::array();
  for (const NamedParams& c : configurations) {
    out.push_back(Json{{"name", c.name}, {"params", c.params}});
  }
  return out;
}

void print_configurations(std::ostream& out, const std::vector<NamedParams>& configurations) {
  for (const NamedParams& c : configurations) {
    std::string params;
    for (const auto& [key, value] : c.params) params += fmt::format(" -p {}={}", key, value);
    out << fmt::format("      configuration {}:{}\n", c.name, params);
  }
}

void print_aliases(std::ostream& out, const EstimatorEntry& e) {
  if (e.aliases.empty()) return;
  out << fmt::format("      also named {} (the same estimator, runs and run ids)\n",
                     fmt::join(e.aliases, ", "));
}

Json estimator_json(const EstimatorEntry& e) {
  Json entry{{"name", e.name},
             {"aliases", e.aliases},
             {"biased", e.biased},
             {"params", params_json(e.params)},
             {"description", e.description},
             {"analytic", e.samples_analytic()},
             {"scenes", e.renders_scenes()},
             {"scene_params", params_json(e.scene_params)},
             {"scene_configurations", configurations_json(e.scene_configurations)}};
  if (e.declared) {
    entry["declared"] = Json{{"integrand", e.declared->integrand},
                             {"params", e.declared->integrand_params},
                             {"samples", e.declared->samples},
                             {"replicates", e.declared->replicates},
                             {"partners", e.declared->partners}};
  }
  return entry;
}

// `list --json`: the estimators (analytic, then scene-only), integrands and scenes.
Json registry_json() {
  Json estimators = Json::array();
  for (const EstimatorEntry& e : estimator_registry()) estimators.push_back(estimator_json(e));
  for (const EstimatorEntry& e : scene_estimator_registry()) {
    estimators.push_back(estimator_json(e));
  }
  Json integrands = Json::array();
  for (const IntegrandEntry& i : integrand_registry()) {
    integrands.push_back(Json{{"name", i.name},
                              {"params", params_json(i.params)},
                              {"exact", i.exact},
                              {"tags", i.tags},
                              {"description", i.description}});
  }
  Json scenes = Json::array();
  for (const IntegrandEntry& i : scene_registry()) {
    scenes.push_back(Json{{"name", i.name},
                          {"params", params_json(i.params)},
                          {"exact", i.exact},
                          {"description", i.description}});
  }
  return Json{{"estimators", estimators}, {"integrands", integrands}, {"scenes", scenes}};
}

void print_estimators(std::ostream& out) {
  out << "estimators:\n";
  for (const EstimatorEntry& e : estimator_registry()) {
    out << fmt::format("  {:<20} {}{}\n", e.name, e.biased ? "[biased] " : "", e.description);
    print_aliases(out, e);
    if (e.declared) {
      out << fmt::format("      biased on {} at {} samples x {} replicates (`verify -e {}`)\n",
                         e.declared->integrand, e.declared->samples, e.declared->replicates,
                         e.name);
    }
    print_params(out, e.params);
    if (e.renders_scenes() && !e.scene_params.empty()) {
      out << "      on scenes:\n";
      print_params(out, e.scene_params);
      print_configurations(out, e.scene_configurations);
    }
  }
  out << "scene-only estimators:\n";
  for (const EstimatorEntry& e : scene_estimator_registry()) {
    out << fmt::format("  {:<20} {}{}\n", e.name, e.biased ? "[biased] " : "", e.description);
    print_aliases(out, e);
    if (e.declared) {
      out << fmt::format(
          "      biased on {} at {} samples per pixel x {} replicates{} (`verify -e {}`)\n",
          e.declared->integrand, e.declared->samples, e.declared->replicates,
          e.declared->partners.empty()
              ? ""
              : fmt::format(", against {}", fmt::join(e.declared->partners, ", ")),
          e.name);
    }
    print_params(out, e.scene_params);
    print_configurations(out, e.scene_configurations);
  }
}

}  // namespace

void print_registry(std::ostream& out, bool as_json) {
  if (as_json) {
    out << registry_json().dump(2) << "\n";
    return;
  }
  print_estimators(out);
  out << "integrands:\n";
  for (const IntegrandEntry& i : integrand_registry()) {
    std::string tags = i.exact ? "[exact] " : "";
    for (const std::string& tag : i.tags) tags += "[" + tag + "] ";
    out << fmt::format("  {:<20} {}{}\n", i.name, tags, i.description);
    print_params(out, i.params);
  }
  out << "scenes (or a scene file: --integrand path/to/scene.json):\n";
  for (const IntegrandEntry& i : scene_registry()) {
    out << fmt::format("  {:<20} {}{}\n", i.name, i.exact ? "[exact] " : "", i.description);
    print_params(out, i.params);
  }
}

CLI::App* add_list_command(CLI::App& app, ListArguments& args) {
  CLI::App* list = app.add_subcommand("list", "estimators, integrands and scenes, with parameters");
  list->add_flag("--json", args.json, "print as JSON");
  return list;
}

int list_command(const ListArguments& args, const CommandContext& context) {
  print_registry(context.out, args.json);
  return kExitOk;
}

}  // namespace pcbench
