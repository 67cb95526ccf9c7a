#include "estimators/registry.h"

#include <fmt/format.h>

#include "estimators/resampling.h"
#include "harness/errors.h"

namespace pcbench {
namespace {

// Parameter declarations shared by the family (estimators/resampling.h documents them).
ParamSpec pool_size_spec() {
  return {.name = "M",
          .type = ParamType::kInt,
          .default_value = "16",
          .description = "light paths in a pool",
          .min = 1,
          .max = 1 << 20};
}
ParamSpec draws_spec() {
  return {.name = "K",
          .type = ParamType::kInt,
          .default_value = "4",
          .description = "connections drawn per camera sample",
          .min = 1,
          .max = 1 << 16};
}
ParamSpec pool_mode_spec() {
  return {.name = "pool",
          .type = ParamType::kChoice,
          .default_value = "fresh",
          .description = "a fresh pool per camera sample, or one shared by a batch of 256",
          .choices = {"fresh", "shared"}};
}

ResamplingConfig config_from(const ResolvedParams& params, Selection selection) {
  ResamplingConfig config{.selection = selection};
  if (params.has("M")) config.M = static_cast<std::uint32_t>(params.integer("M"));
  if (params.has("K")) config.K = static_cast<std::uint32_t>(params.integer("K"));
  if (params.has("pool") && params.text("pool") == "shared") config.pool = PoolMode::kShared;
  if (params.has("importance")) {
    const std::string& source = params.text("importance");
    config.importance = source == "f"         ? ImportanceSource::kF
                        : source == "uniform" ? ImportanceSource::kUniform
                                              : ImportanceSource::kApproximate;
  }
  if (params.has("uniform_mix")) config.uniform_mix = params.real("uniform_mix");
  if (params.has("sampler")) {
    config.sampler =
        params.text("sampler") == "alias" ? DiscreteSamplerKind::kAlias : DiscreteSamplerKind::kCdf;
  }
  return config;
}

EstimatorEntry family_entry(std::string name, std::string description,
                            std::vector<ParamSpec> params, Selection selection) {
  return {.name = std::move(name),
          .description = std::move(description),
          .params = std::move(params),
          .make = [selection](const ResolvedParams& resolved) -> std::unique_ptr<Estimator> {
            return std::make_unique<ResamplingEstimator>(config_from(resolved, selection));
          }};
}

}  // namespace

const std::vector<EstimatorEntry>& estimator_registry() {
  static const std::vector<EstimatorEntry> table = {
      family_entry("plain", "one fresh light path per camera sample, connected once (M = K = 1)",
                   {}, Selection::kAll),
      family_entry("vc-all", "vertex connection to every light path of a pool of M",
                   {pool_size_spec(), pool_mode_spec()}, Selection::kAll),
      family_entry("lvc", "light vertex cache: K uniform draws from the pool's M light vertices",
                   {pool_size_spec(), draws_spec(), pool_mode_spec()}, Selection::kUniform),
      family_entry(
          "pcbpt", "probabilistic connections: K draws from P ∝ importance, mixed with uniform",
          {pool_size_spec(),
           draws_spec(),
           pool_mode_spec(),
           {.name = "importance",
            .type = ParamType::kChoice,
            .default_value = "approx",
            .description = "resampling importance: the integrand's approximation, |f|, or 1",
            .choices = {"approx", "f", "uniform"}},
           {.name = "uniform_mix",
            .type = ParamType::kReal,
            .default_value = "0.1",
            .description = "fraction of P spread uniformly over the pool",
            .min = 0,
            .max = 1},
           {.name = "sampler",
            .type = ParamType::kChoice,
            .default_value = "cdf",
            .description = "how K indices are drawn from P: alias table or inverse CDF",
            .choices = {"cdf", "alias"}}},
          Selection::kImportance),
  };
  return table;
}

const EstimatorEntry& find_estimator(const std::string& name) {
  std::vector<std::string> names;
  for (const EstimatorEntry& entry : estimator_registry()) {
    if (entry.name == name) return entry;
    names.push_back(entry.name);
  }
  throw InputError(
      fmt::format("unknown estimator '{}'; valid estimators: {}", name, join_names(names)));
}

}  // namespace pcbench
