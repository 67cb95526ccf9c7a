#include "estimators/negative_controls.h"

#include <fmt/format.h>
#include <cmath>

#include "base/errors.h"
#include "estimators/family_params.h"
#include "estimators/reservoir_params.h"

namespace pcbench {
namespace {

// The base every control starts from: probabilistic connections by the approximate importance
// (M and K come from the parameters).
ResamplingConfig importance_base(double uniform_mix, Flaw flaw) {
  return {.step = {.selection = Selection::kImportance,
                   .scheme = DrawScheme::kIndependent,
                   .uniform_mix = uniform_mix,
                   .flaw = flaw},
          .importance = ImportanceSource::kApproximate};
}

using Adjust = std::function<void(ResamplingConfig&, const ResolvedParams&)>;

EstimatorEntry control(std::string name, std::string description, std::vector<ParamSpec> params,
                       ResamplingConfig base, DeclaredWorkload declared, Adjust adjust = {}) {
  return {.name = std::move(name),
          .description = std::move(description),
          .biased = true,
          .params = std::move(params),
          .make = [base, adjust](const ResolvedParams& resolved) -> std::unique_ptr<Estimator> {
            ResamplingConfig config = config_from(resolved, base);
            if (adjust) adjust(config, resolved);
            return std::make_unique<ResamplingEstimator>(config);
          },
          .declared = std::move(declared)};
}

DeclaredWorkload workload(std::string integrand, ParamText params = {}) {
  return {.integrand = std::move(integrand),
          .integrand_params = std::move(params),
          .samples = 100000,
          .replicates = 32};
}

// A reuse control: restir with target |f| (visibility in the targets, so that neighbours' supports
// differ) and its flaw set from the severity by `adjust`.
EstimatorEntry reuse_control(std::string name, std::string description, std::string severity,
                             ReservoirConfig base, ReservoirAdjust adjust) {
  base.pool = PoolMode::kShared;
  base.target = ImportanceSource::kF;
  base.neighbours = 4;
  base.rounds = 1;
  EstimatorEntry entry = reservoir_entry(
      std::move(name), std::move(description),
      {pool_size_spec(16, 1, kReuseMaxM), neighbours_spec(), severity_spec(std::move(severity))},
      base, std::move(adjust));
  entry.biased = true;
  entry.declared = workload("blocker");
  return entry;
}

}  // namespace

std::vector<EstimatorEntry> negative_control_entries() {
  std::vector<EstimatorEntry> entries;
  entries.push_back(control(
      "ctl-cached-visibility",
      "(a) importance |f| at the cell's cache point, no uniform mixing (P = 0 where the "
      "cache point is occluded but the camera path is not)",
      {pool_size_spec(), draws_spec(),
       severity_spec("cache cell width (cells per dimension = 1 / severity)")},
      [] {
        ResamplingConfig base = importance_base(0.0, Flaw::kNone);
        base.importance = ImportanceSource::kCached;
        return base;
      }(),
      workload("blocker"),
      [](ResamplingConfig& config, const ResolvedParams& params) {
        const double width = params.real("severity");
        config.cache_cells =
            width > 0.0 ? static_cast<std::uint32_t>(std::min(65536.0, std::ceil(1.0 / width)))
                        : 65536;
      }));
  entries.push_back(control(
      "ctl-cull-small",
      "(b) importances below severity x the pool's largest set to 0, no uniform mixing",
      {pool_size_spec(), draws_spec(), severity_spec("cull threshold, relative to the largest")},
      importance_base(0.0, Flaw::kCullSmall), workload("genz-gaussian")));
  entries.push_back(
      control("ctl-wrong-count", "(c) the estimate divided by M - severity instead of M",
              {pool_size_spec(16, 2), draws_spec(), severity_spec("error in the count")},
              importance_base(0.1, Flaw::kWrongCount), workload("form-factor")));
  entries.push_back(control(
      "ctl-best-draw",
      "(d) outcome-selected reuse, a share of the estimate from the draw that contributed "
      "most, weighted as the only draw",
      {pool_size_spec(), draws_spec(), severity_spec("share of the estimate from the best draw")},
      importance_base(0.1, Flaw::kBestDraw), workload("genz-gaussian")));
  entries.push_back(control(
      "ctl-renormalise-kept",
      "(e) candidates below severity x the largest importance dropped, estimate divided "
      "by the number kept",
      {pool_size_spec(), draws_spec(), severity_spec("drop threshold, relative to the largest")},
      importance_base(0.0, Flaw::kRenormaliseKept), workload("genz-gaussian")));
  entries.push_back(control(
      "ctl-foreign-normaliser",
      "(f) draws from P on this pool, weighted by a P normalised by another pool's "
      "importances",
      {pool_size_spec(4), draws_spec(), severity_spec("share of the other pool in the normaliser")},
      importance_base(0.1, Flaw::kForeignNormaliser), workload("genz-gaussian")));
  entries.push_back(control(
      "ctl-without-replacement",
      "(g) K draws without replacement weighted as if with replacement, 1 / (M K P)",
      {pool_size_spec(8), draws_spec(6), severity_spec("non-uniformity of P (uniform mix 1 - s)")},
      [] {
        ResamplingConfig base = importance_base(0.0, Flaw::kNone);
        base.step.scheme = DrawScheme::kWithoutReplacement;
        return base;
      }(),
      workload("blocker"),
      [](ResamplingConfig& config, const ResolvedParams& params) {
        if (config.step.K > config.step.M) {
          throw InputError(fmt::format(
              "ctl-without-replacement: K = {} draws without replacement need K <= M = {}",
              config.step.K, config.step.M));
        }
        config.step.uniform_mix = 1.0 - params.real("severity");
      }));
  entries.push_back(reuse_control(
      "ctl-naive-reuse",
      "restir with target |f| and the naive reuse weights 1/(k+1) (Bitterli 2020's biased 1/ΣM)",
      "share of the naive weights (the rest 1/Z)", {.weighting = {.form = ReuseWeights::kUniform}},
      [](ReservoirConfig& config, const ResolvedParams& params) {
        config.weighting.naive_share = params.real("severity");
      }));
  entries.push_back(reuse_control(
      "ctl-reuse-unshadowed",
      "restir with target |f| whose balance weights see the neighbours' targets without "
      "visibility",
      "share of the unoccluded approximation in the neighbours' weight targets", {},
      [](ReservoirConfig& config, const ResolvedParams& params) {
        config.unshadowed_share = params.real("severity");
      }));
  return entries;
}

}  // namespace pcbench
