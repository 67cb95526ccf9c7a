#include "estimators/registry.h"

#include <fmt/format.h>

#include "estimators/family_params.h"
#include "estimators/negative_controls.h"
#include "estimators/resampling.h"
#include "estimators/scene_estimators.h"
#include "harness/errors.h"
#include "harness/nearest_name.h"

namespace pcbench {
namespace {

EstimatorEntry family_entry(std::string name, std::string description,
                            std::vector<ParamSpec> params, Selection selection, DrawScheme scheme) {
  const ResamplingConfig base{.step = {.selection = selection, .scheme = scheme}};
  return {.name = std::move(name),
          .description = std::move(description),
          .params = std::move(params),
          .make = [base](const ResolvedParams& resolved) -> std::unique_ptr<Estimator> {
            return std::make_unique<ResamplingEstimator>(config_from(resolved, base));
          }};
}

std::vector<EstimatorEntry> make_table() {
  std::vector<EstimatorEntry> table = {
      family_entry("plain", "one fresh light path per camera sample, connected once (M = K = 1)",
                   {}, Selection::kAll, DrawScheme::kEvery),
      family_entry("vc-all", "vertex connection to every light path of a pool of M",
                   {pool_size_spec(), pool_mode_spec()}, Selection::kAll, DrawScheme::kEvery),
      family_entry("lvc", "light vertex cache: K uniform draws from the pool's M light vertices",
                   {pool_size_spec(), draws_spec(), pool_mode_spec(), draw_scheme_spec()},
                   Selection::kUniform, DrawScheme::kIndependent),
      family_entry("pcbpt",
                   "probabilistic connections: K draws from P ∝ importance, mixed with uniform",
                   {pool_size_spec(), draws_spec(), pool_mode_spec(), draw_scheme_spec(),
                    importance_spec(), uniform_mix_spec(), sampler_spec(), cache_cells_spec()},
                   Selection::kImportance, DrawScheme::kIndependent),
  };
  for (EstimatorEntry& entry : negative_control_entries()) table.push_back(std::move(entry));
  add_scene_forms(table);
  return table;
}

}  // namespace

const std::vector<EstimatorEntry>& estimator_registry() {
  static const std::vector<EstimatorEntry> table = make_table();
  return table;
}

const std::vector<EstimatorEntry>& scene_estimator_registry() {
  static const std::vector<EstimatorEntry> table = scene_only_estimators();
  return table;
}

const EstimatorEntry& find_estimator(const std::string& name) {
  std::vector<std::string> names;
  for (const auto* table : {&estimator_registry(), &scene_estimator_registry()}) {
    for (const EstimatorEntry& entry : *table) {
      if (entry.name == name) return entry;
      names.push_back(entry.name);
    }
  }
  throw InputError(fmt::format("unknown estimator '{}'{}; valid estimators: {}", name,
                               did_you_mean(name, names), join_names(names)));
}

}  // namespace pcbench
