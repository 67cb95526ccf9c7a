// Parameter declarations of the reservoir estimators (ris, restir and the reuse controls), the
// reading of resolved parameters into a ReservoirConfig, and their registry rows.
#pragma once

#include <string>
#include <vector>

#include "base/params.h"
#include "estimators/registry.h"
#include "estimators/reservoir_estimator.h"

namespace pcbench {

// Reuse reads a whole batch of kBatchSize camera samples with their shared pool at once: M is
// bounded so that a batch's candidate pairs stay within 2^20, as the family's parts do.
inline constexpr int kReuseMaxM = 4096;

ParamSpec target_spec();
ParamSpec neighbours_spec();
ParamSpec rounds_spec();
ParamSpec reuse_weights_spec();
// The form a choice of reuse_weights_spec names.
ReuseWeights reuse_weights_named(const std::string& choice);

// The config of `base` with every reservoir parameter present in `params` applied (M, K, pool,
// target, N, rounds, weights; a control's severity is read by the control).
ReservoirConfig reservoir_config_from(const ResolvedParams& params, ReservoirConfig base);

// The row of an analytic reservoir estimator; `adjust` applies what only it reads (severity).
using ReservoirAdjust = std::function<void(ReservoirConfig&, const ResolvedParams&)>;
EstimatorEntry reservoir_entry(std::string name, std::string description,
                               std::vector<ParamSpec> params, ReservoirConfig base,
                               ReservoirAdjust adjust = {});

}  // namespace pcbench
