#include "harness/verify/exact_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "estimators/resampling.h"

namespace pcbench {
namespace {

// Per-case figures.
struct CaseCheck {
  std::uint64_t sequences = 0;
  double scaled_error = 0.0;
  std::uint32_t support_violations = 0;
  double multiplicity_error = 0.0;
};

CaseCheck check_case(const ResamplingStep& step, const PoolView& view) {
  const std::uint32_t m = step.config().M;
  CaseCheck out;
  std::vector<double> pmf;
  step.build_pmf(view, pmf);
  for (std::uint32_t j = 0; j < m; ++j) {
    if (view.contributions[j] != 0.0 && pmf[j] == 0.0) ++out.support_violations;
  }

  double expectation = 0.0;
  double magnitude = 0.0;  // E[Σ |coefficient × contribution|]: the scale of rounding
  std::vector<double> counts(m, 0.0);
  step.enumerate(view, [&](double probability, std::span<const Term> terms) {
    ++out.sequences;
    for (const Term& term : terms) {
      const double value = term.coefficient * view.contributions[term.index];
      expectation += probability * value;
      magnitude += probability * std::fabs(value);
    }
    // Multiplicities of the draws themselves (a control's extra term is not a draw).
    const std::size_t draws = step.config().scheme == DrawScheme::kEvery
                                  ? m
                                  : std::min<std::size_t>(terms.size(), step.config().K);
    for (std::size_t t = 0; t < draws; ++t) counts[terms[t].index] += probability;
  });

  double connect_all = 0.0;
  double connect_all_magnitude = 0.0;
  for (double c : view.contributions) {
    connect_all += c / m;
    connect_all_magnitude += std::fabs(c) / m;
  }
  const double scale = std::max(magnitude, connect_all_magnitude);
  out.scaled_error = scale > 0.0 ? std::fabs(expectation - connect_all) / scale
                                 : std::fabs(expectation - connect_all);
  if (std::isnan(expectation)) out.scaled_error = std::numeric_limits<double>::infinity();

  const double draws_per_sample =
      step.config().scheme == DrawScheme::kEvery ? m : static_cast<double>(step.config().K);
  for (std::uint32_t j = 0; j < m; ++j) {
    out.multiplicity_error =
        std::max(out.multiplicity_error, std::fabs(counts[j] - draws_per_sample * pmf[j]));
  }
  return out;
}

}  // namespace

ExactCheck exact_check(const RunPlan& plan, std::uint64_t seed) {
  ExactCheck out;
  const auto* estimator = dynamic_cast<const ResamplingEstimator*>(plan.made_estimator.get());
  if (estimator == nullptr) {
    out.result = "inconclusive";
    out.reason = "not a resampling estimator: there is no resampling step to enumerate";
    return out;
  }
  out.applicable = true;
  ResamplingConfig config = estimator->config();
  config.step.M = std::min(config.step.M, kExactMaxM);
  config.step.K = config.step.scheme == DrawScheme::kEvery ? config.step.M
                                                           : std::min(config.step.K, kExactMaxK);
  const ResamplingEstimator small(config);
  out.M = config.step.M;
  out.K = config.step.K;

  const std::unique_ptr<PathWorkspace> paths = plan.made_integrand->make_workspace();
  EstimatorScratch scratch;
  const BatchContext ctx{.key = run_key(seed, plan.stream_hash), .sample_count = kExactCases};
  const PreparedPools pools = small.prepare(ctx, *paths, scratch, true);
  out.cases = pools.samples;
  for (std::uint32_t i = 0; i < pools.samples; ++i) {
    const CaseCheck c = check_case(small.step(), small.pool_view(pools, scratch, i));
    out.sequences += c.sequences;
    out.support_violations += c.support_violations;
    out.max_scaled_error = std::max(out.max_scaled_error, c.scaled_error);
    out.max_multiplicity_error = std::max(out.max_multiplicity_error, c.multiplicity_error);
    if (!(c.scaled_error <= kExactTolerance)) ++out.expectation_failures;
  }

  const bool biased = out.expectation_failures > 0;
  out.result = biased ? "biased" : "consistent";
  out.reason = fmt::format(
      "{} of {} (y, X) cases at M = {}, K = {}: E over {} enumerated draw sequences {} "
      "connect-to-all (largest error {:.2g} of the scale); {} support violations (f != 0, "
      "P = 0); largest |E[count_j] - K P_j| = {:.2g}",
      biased ? out.expectation_failures : out.cases, out.cases, out.M, out.K, out.sequences,
      biased ? "misses" : "equals", out.max_scaled_error, out.support_violations,
      out.max_multiplicity_error);
  return out;
}

}  // namespace pcbench
