#include "estimators/family_params.h"

#include <memory>
#include <string>

namespace pcbench {

ParamSpec pool_size_spec(int default_value, int min, int max) {
  return {.name = "M",
          .type = ParamType::kInt,
          .default_value = std::to_string(default_value),
          .description = "light paths in a pool",
          .min = static_cast<double>(min),
          .max = static_cast<double>(max)};
}
ParamSpec draws_spec(int default_value) {
  return {.name = "K",
          .type = ParamType::kInt,
          .default_value = std::to_string(default_value),
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
ParamSpec draw_scheme_spec() {
  return {.name = "draws",
          .type = ParamType::kChoice,
          .default_value = "independent",
          .description = "K draws with replacement, or stratified or systematic (inverse CDF)",
          .choices = {"independent", "stratified", "systematic"}};
}
ParamSpec importance_spec() {
  return {.name = "importance",
          .type = ParamType::kChoice,
          .default_value = "approx",
          .description =
              "resampling importance: the integrand's approximation, |f|, 1, |f| at the cell's "
              "cache point, or a positive one large where f is small",
          .choices = {"approx", "f", "uniform", "cached", "adversarial"}};
}
ParamSpec uniform_mix_spec() {
  return {.name = "uniform_mix",
          .type = ParamType::kReal,
          .default_value = "0.1",
          .description = "fraction of P spread uniformly over the pool",
          .min = 0,
          .max = 1};
}
ParamSpec sampler_spec() {
  return {.name = "sampler",
          .type = ParamType::kChoice,
          .default_value = "cdf",
          .description = "how independent draws are made from P: alias table or inverse CDF",
          .choices = {"cdf", "alias"}};
}
ParamSpec cache_cells_spec() {
  return {.name = "cache_cells",
          .type = ParamType::kInt,
          .default_value = "4",
          .description = "cache cells per camera dimension for importance=cached",
          .min = 1,
          .max = 1 << 16};
}
ParamSpec severity_spec(std::string what) {
  return {.name = "severity",
          .type = ParamType::kReal,
          .default_value = "1",
          .description = std::move(what),
          .min = 0,
          .max = 1};
}

ResamplingConfig config_from(const ResolvedParams& params, ResamplingConfig config) {
  StepConfig& step = config.step;
  if (params.has("M")) step.M = static_cast<std::uint32_t>(params.integer("M"));
  if (params.has("K")) step.K = static_cast<std::uint32_t>(params.integer("K"));
  if (params.has("pool") && params.text("pool") == "shared") config.pool = PoolMode::kShared;
  if (params.has("draws")) {
    const std::string& scheme = params.text("draws");
    step.scheme = scheme == "stratified"   ? DrawScheme::kStratified
                  : scheme == "systematic" ? DrawScheme::kSystematic
                                           : DrawScheme::kIndependent;
  }
  if (params.has("importance")) {
    const std::string& source = params.text("importance");
    config.importance = source == "f"             ? ImportanceSource::kF
                        : source == "uniform"     ? ImportanceSource::kUniform
                        : source == "cached"      ? ImportanceSource::kCached
                        : source == "adversarial" ? ImportanceSource::kAdversarial
                                                  : ImportanceSource::kApproximate;
  }
  if (params.has("uniform_mix")) step.uniform_mix = params.real("uniform_mix");
  if (params.has("sampler")) {
    step.sampler =
        params.text("sampler") == "alias" ? DiscreteSamplerKind::kAlias : DiscreteSamplerKind::kCdf;
  }
  if (params.has("cache_cells")) {
    config.cache_cells = static_cast<std::uint32_t>(params.integer("cache_cells"));
  }
  if (params.has("severity")) step.severity = params.real("severity");
  if (step.scheme == DrawScheme::kEvery) step.K = step.M;
  return config;
}

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

}  // namespace pcbench
