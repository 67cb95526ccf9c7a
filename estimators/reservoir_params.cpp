#include "estimators/reservoir_params.h"

#include <memory>

namespace pcbench {

ParamSpec target_spec() {
  return {.name = "target",
          .type = ParamType::kChoice,
          .default_value = "approx",
          .description =
              "target p̂ of the resampling: the integrand's approximation (pcbpt's "
              "importance=approx), |f| itself, or 1",
          .choices = {"approx", "f", "uniform"}};
}
ParamSpec neighbours_spec() {
  return {.name = "N",
          .type = ParamType::kInt,
          .default_value = "4",
          .description =
              "neighbours per reuse: the next N camera samples of the batch (mod its "
              "size)",
          .min = 1,
          .max = kMaxReuseNeighbours};
}
ParamSpec rounds_spec() {
  return {.name = "rounds",
          .type = ParamType::kInt,
          .default_value = "1",
          .description = "rounds of spatial reuse, each from the previous round's reservoirs",
          .min = 1,
          .max = 4};
}
ParamSpec reuse_weights_spec() {
  return {.name = "weights",
          .type = ParamType::kChoice,
          .default_value = "balance",
          .description =
              "MIS weights of the reuse: generalized balance heuristic, defensive "
              "pairwise MIS, or 1/Z over the sources whose target is > 0",
          .choices = {"balance", "pairwise", "count"}};
}

ReuseWeights reuse_weights_named(const std::string& choice) {
  return choice == "pairwise" ? ReuseWeights::kPairwise
         : choice == "count"  ? ReuseWeights::kCount
                              : ReuseWeights::kBalance;
}

ReservoirConfig reservoir_config_from(const ResolvedParams& params, ReservoirConfig config) {
  if (params.has("M")) config.M = static_cast<std::uint32_t>(params.integer("M"));
  if (params.has("K")) config.K = static_cast<std::uint32_t>(params.integer("K"));
  if (params.has("pool")) {
    config.pool = params.text("pool") == "shared" ? PoolMode::kShared : PoolMode::kFresh;
  }
  if (params.has("target")) {
    const std::string& target = params.text("target");
    config.target = target == "f"         ? ImportanceSource::kF
                    : target == "uniform" ? ImportanceSource::kUniform
                                          : ImportanceSource::kApproximate;
  }
  if (params.has("N")) config.neighbours = static_cast<std::uint32_t>(params.integer("N"));
  if (params.has("rounds")) config.rounds = static_cast<std::uint32_t>(params.integer("rounds"));
  if (params.has("weights")) config.weighting.form = reuse_weights_named(params.text("weights"));
  return config;
}

EstimatorEntry reservoir_entry(std::string name, std::string description,
                               std::vector<ParamSpec> params, ReservoirConfig base,
                               ReservoirAdjust adjust) {
  return {.name = std::move(name),
          .description = std::move(description),
          .params = std::move(params),
          .make = [base, adjust](const ResolvedParams& resolved) -> std::unique_ptr<Estimator> {
            ReservoirConfig config = reservoir_config_from(resolved, base);
            if (adjust) adjust(config, resolved);
            return std::make_unique<ReservoirEstimator>(config);
          }};
}

}  // namespace pcbench
