#include "estimators/registry.h"

#include <fmt/format.h>

#include "base/errors.h"
#include "base/name_lookup.h"
#include "base/nearest_name.h"
#include "estimators/family_params.h"
#include "estimators/negative_controls.h"
#include "estimators/resampling.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {
namespace {

// A member of the family: its analytic form (the resampling estimator with `selection` and
// `scheme`) and its scene form (estimators/scene/), in one row.
EstimatorEntry family_entry(std::string name, std::string description,
                            std::vector<ParamSpec> params, Selection selection, DrawScheme scheme,
                            SceneForm scene) {
  const ResamplingConfig base{.step = {.selection = selection, .scheme = scheme}};
  return {.name = std::move(name),
          .description = std::move(description),
          .params = std::move(params),
          .make = [base](const ResolvedParams& resolved) -> std::unique_ptr<Estimator> {
            return std::make_unique<ResamplingEstimator>(config_from(resolved, base));
          },
          .scene_params = std::move(scene.params),
          .make_render = std::move(scene.make)};
}

std::vector<EstimatorEntry> make_table() {
  std::vector<EstimatorEntry> table = {
      family_entry("plain", "one fresh light path per camera sample, connected once (M = K = 1)",
                   {}, Selection::kAll, DrawScheme::kEvery, plain_scene_form()),
      family_entry("vc-all", "vertex connection to every light path of a pool of M",
                   {pool_size_spec(), pool_mode_spec()}, Selection::kAll, DrawScheme::kEvery,
                   vc_all_scene_form()),
      family_entry("lvc", "light vertex cache: K uniform draws from the pool's M light vertices",
                   {pool_size_spec(), draws_spec(), pool_mode_spec(), draw_scheme_spec()},
                   Selection::kUniform, DrawScheme::kIndependent, lvc_scene_form()),
      family_entry("pcbpt",
                   "probabilistic connections: K draws from P ∝ importance, mixed with uniform",
                   {pool_size_spec(), draws_spec(), pool_mode_spec(), draw_scheme_spec(),
                    importance_spec(), uniform_mix_spec(), sampler_spec(), cache_cells_spec()},
                   Selection::kImportance, DrawScheme::kIndependent, pcbpt_scene_form()),
  };
  for (EstimatorEntry& entry : negative_control_entries()) table.push_back(std::move(entry));
  return table;
}

// The estimators of scenes only. Rows registered later (register_scene_estimator) go after.
std::vector<EstimatorEntry>& scene_table() {
  static std::vector<EstimatorEntry> table = {
      pt_entry(), lt_entry(), ctl_scene_visible_only_entry(), ctl_scene_lvc_per_vertex_entry(),
      ctl_scene_nee_count_entry()};
  return table;
}

}  // namespace

const std::vector<EstimatorEntry>& estimator_registry() {
  static const std::vector<EstimatorEntry> table = make_table();
  return table;
}

const std::vector<EstimatorEntry>& scene_estimator_registry() {
  return scene_table();
}

void register_scene_estimator(EstimatorEntry entry) {
  scene_table().push_back(std::move(entry));
}

const EstimatorEntry& find_estimator(const std::string& name) {
  std::vector<std::string> names;
  const EstimatorEntry* found =
      find_by_name({&estimator_registry(), &scene_estimator_registry()}, name, names);
  if (found) return *found;
  throw InputError(fmt::format("unknown estimator '{}'{}; valid estimators: {}", name,
                               did_you_mean(name, names), join_names(names)));
}

std::shared_ptr<const scene::SceneEstimator> make_scene_estimator(const std::string& name,
                                                                  const ParamText& params) {
  const EstimatorEntry& entry = find_estimator(name);
  if (!entry.renders_scenes()) {
    throw InputError(fmt::format("estimator '{}' does not render scenes", name));
  }
  return entry.make_render(resolve_params(entry.scene_params, params, name));
}

}  // namespace pcbench
