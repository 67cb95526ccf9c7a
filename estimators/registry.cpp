#include "estimators/registry.h"

#include <fmt/format.h>

#include "base/errors.h"
#include "base/name_lookup.h"
#include "base/nearest_name.h"
#include "estimators/negative_controls.h"

namespace pcbench {

// The estimators, one line each, in the order of `pcbench list`: the function its file defines
// (estimators/scene/<key>.cpp for the family and the scene estimators), which returns its whole
// row. ESTIMATOR(f) declares f here and calls it in make_tables() below; a new line goes above
// the last, which ends the list.
#define PCBENCH_ESTIMATORS(ESTIMATOR) \
  ESTIMATOR(plain_entry) \
  ESTIMATOR(vc_all_entry) \
  ESTIMATOR(lvc_entry) \
  ESTIMATOR(pcbpt_entry) \
  ESTIMATOR(ris_entry) \
  ESTIMATOR(restir_entry) \
  ESTIMATOR(pt_entry) \
  ESTIMATOR(lt_entry) \
  ESTIMATOR(ctl_scene_visible_only_entry) \
  ESTIMATOR(ctl_scene_lvc_per_vertex_entry) \
  ESTIMATOR(ctl_scene_nee_count_entry) \
  ESTIMATOR(ctl_scene_naive_reuse_entry) \
  ESTIMATOR(ctl_scene_reuse_unshadowed_entry) \
  /* the end of the list */

PCBENCH_ESTIMATORS(PCBENCH_DECLARE_ENTRY)

namespace {

// The rows with an analytic form (most render scenes too) and those of scenes only, in list
// order: the estimators above, then the analytic negative controls (negative_controls.h, one
// file). Rows registered later (register_scene_estimator) go after the scene ones.
struct Tables {
  std::vector<EstimatorEntry> analytic;
  std::vector<EstimatorEntry> scene_only;
};

Tables make_tables() {
  std::vector<EstimatorEntry> rows = {PCBENCH_ESTIMATORS(PCBENCH_CALL_ENTRY)};
  for (EstimatorEntry& entry : negative_control_entries()) rows.push_back(std::move(entry));
  Tables tables;
  for (EstimatorEntry& entry : rows) {
    (entry.samples_analytic() ? tables.analytic : tables.scene_only).push_back(std::move(entry));
  }
  return tables;
}

Tables& tables() {
  static Tables tables = make_tables();
  return tables;
}

}  // namespace

const std::vector<EstimatorEntry>& estimator_registry() {
  return tables().analytic;
}

const std::vector<EstimatorEntry>& scene_estimator_registry() {
  return tables().scene_only;
}

void register_scene_estimator(EstimatorEntry entry) {
  tables().scene_only.push_back(std::move(entry));
}

const EstimatorEntry& find_estimator(const std::string& name) {
  std::vector<std::string> names;
  const EstimatorEntry* found =
      find_by_name({&estimator_registry(), &scene_estimator_registry()}, name, names);
  if (found) return *found;
  for (const auto* table : {&estimator_registry(), &scene_estimator_registry()}) {
    for (const EstimatorEntry& entry : *table) {
      for (const std::string& alias : entry.aliases) {
        if (alias == name) return entry;
        names.push_back(alias);
      }
    }
  }
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
