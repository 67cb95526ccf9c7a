// Parameter declarations of the resampling family (estimators/resampling.h documents them), the
// reading of resolved parameters into a ResamplingConfig, shared by the estimators and the
// negative controls, and a member's registry row.
#pragma once

#include <string>
#include <vector>

#include "base/params.h"
#include "estimators/registry.h"
#include "estimators/resampling.h"
#include "estimators/scene/scene_form.h"

namespace pcbench {

// Defaults differ between estimators: a negative control picks the M and K where its flaw shows.
ParamSpec pool_size_spec(int default_value = 16, int min = 1, int max = 1 << 20);
ParamSpec draws_spec(int default_value = 4);
ParamSpec pool_mode_spec();
ParamSpec draw_scheme_spec();
ParamSpec importance_spec();
ParamSpec uniform_mix_spec();
ParamSpec sampler_spec();
ParamSpec cache_cells_spec();
ParamSpec severity_spec(std::string what);

// The config of `base` with every family parameter present in `params` applied.
ResamplingConfig config_from(const ResolvedParams& params, ResamplingConfig base);

// The row of a member of the family: its analytic form (the resampling estimator with
// `selection` and `scheme`, reading `params`) and its scene form (estimators/scene/<key>.cpp).
EstimatorEntry family_entry(std::string name, std::string description,
                            std::vector<ParamSpec> params, Selection selection, DrawScheme scheme,
                            SceneForm scene);

}  // namespace pcbench
