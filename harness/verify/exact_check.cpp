#include "harness/verify/exact_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>

#include "estimators/resampling.h"
#include "estimators/reservoir_estimator.h"

namespace pcbench {
namespace {

// Per-case figures.
struct CaseCheck {
  std::uint64_t sequences = 0;
  double scaled_error = 0.0;
  std::uint32_t support_violations = 0;
  double multiplicity_error = 0.0;
};

using Visit = std::function<void(double, std::span<const Term>)>;
using Enumeration = std::function<void(const Visit&)>;

// What every draw sequence of one camera sample's enumeration adds up to: its expectation against
// connecting to the whole pool, (1/M) Σ_j contribution_j. `draws` is the number of a sequence's
// terms that are draws (a control's extra term is not); `pmf`, when not empty, the P whose K P_j
// the draws must meet in expectation. Without one, a support violation is a j with f != 0 that no
// sequence draws.
CaseCheck check_enumeration(std::span<const double> contributions, const Enumeration& enumerate,
                            std::size_t draws, std::span<const double> pmf) {
  const auto m = static_cast<std::uint32_t>(contributions.size());
  CaseCheck out;
  double expectation = 0.0;
  double magnitude = 0.0;  // E[Σ |coefficient × contribution|]: the scale of rounding
  std::vector<double> counts(m, 0.0);
  enumerate([&](double probability, std::span<const Term> terms) {
    ++out.sequences;
    for (const Term& term : terms) {
      const double value = term.coefficient * contributions[term.index];
      expectation += probability * value;
      magnitude += probability * std::fabs(value);
    }
    // Multiplicities of the draws themselves (a control's extra term is not a draw).
    const std::size_t drawn = std::min(terms.size(), draws);
    for (std::size_t t = 0; t < drawn; ++t) counts[terms[t].index] += probability;
  });

  double connect_all = 0.0;
  double connect_all_magnitude = 0.0;
  for (double c : contributions) {
    connect_all += c / m;
    connect_all_magnitude += std::fabs(c) / m;
  }
  const double scale = std::max(magnitude, connect_all_magnitude);
  out.scaled_error = scale > 0.0 ? std::fabs(expectation - connect_all) / scale
                                 : std::fabs(expectation - connect_all);
  if (std::isnan(expectation)) out.scaled_error = std::numeric_limits<double>::infinity();

  for (std::uint32_t j = 0; j < m; ++j) {
    const double possible = pmf.empty() ? counts[j] : pmf[j];
    if (contributions[j] != 0.0 && possible == 0.0) ++out.support_violations;
    if (pmf.empty()) continue;
    out.multiplicity_error = std::max(out.multiplicity_error,
                                      std::fabs(counts[j] - static_cast<double>(draws) * pmf[j]));
  }
  return out;
}

CaseCheck check_case(const ResamplingStep& step, const PoolView& view) {
  std::vector<double> pmf;
  step.build_pmf(view, pmf);
  const std::size_t draws =
      step.config().scheme == DrawScheme::kEvery ? step.config().M : step.config().K;
  return check_enumeration(
      view.contributions, [&](const Visit& visit) { step.enumerate(view, visit); }, draws, pmf);
}

// Adds one case's figures to the check's.
void add_case(const CaseCheck& c, ExactCheck& out) {
  out.sequences += c.sequences;
  out.support_violations += c.support_violations;
  out.max_scaled_error = std::max(out.max_scaled_error, c.scaled_error);
  out.max_multiplicity_error = std::max(out.max_multiplicity_error, c.multiplicity_error);
  if (!(c.scaled_error <= kExactTolerance)) ++out.expectation_failures;
}

// The reservoir estimators (ris, restir, the reuse controls), cut to what enumerates quickly:
// M <= kExactMaxM, K <= kExactMaxK, rounds <= kExactMaxRounds and N <= kExactMaxNeighbours /
// rounds (the sequences of one case number up to M^(K + N rounds) (N + 1)^(...)). Each case is
// camera sample i of one batch of kExactCases samples sharing the pool (or each with its own).
ExactCheck exact_check_reservoir(const ReservoirEstimator& estimator, const RunPlan& plan,
                                 std::uint64_t seed) {
  ExactCheck out;
  out.applicable = true;
  ReservoirConfig config = estimator.config();
  config.M = std::min(config.M, kExactMaxM);
  config.K = std::min(config.K, kExactMaxK);
  config.rounds = std::min(config.rounds, kExactMaxRounds);
  if (config.rounds > 0) {
    config.neighbours = std::min(config.neighbours, kExactMaxNeighbours / config.rounds);
  }
  const ReservoirEstimator small(config);
  out.M = config.M;
  out.K = config.K;

  const std::unique_ptr<PathWorkspace> paths = plan.made_integrand->make_workspace();
  EstimatorScratch scratch;
  const BatchContext ctx{.key = run_key(seed, plan.stream_hash), .sample_count = kExactCases};
  const ReservoirBatch batch = small.prepare(ctx, *paths, scratch, true);
  out.cases = batch.pools.samples;
  std::vector<double> pmf;
  for (std::uint32_t i = 0; i < batch.pools.samples; ++i) {
    const std::span<const double> contributions =
        std::span<const double>(scratch.contributions).subspan(std::size_t{i} * config.M, config.M);
    if (config.rounds == 0) {
      // RIS: the reservoirs must keep j with P = w_j / Σ w, K times in expectation.
      const std::span<const double> target =
          batch.target.subspan(std::size_t{i} * config.M, config.M);
      const std::span<const double> q =
          batch.light_pdf.subspan(batch.pools.pool_start(i), config.M);
      pmf.resize(config.M);
      double total = 0.0;
      for (std::uint32_t j = 0; j < config.M; ++j) total += pmf[j] = target[j] / q[j];
      for (double& p : pmf) p = total > 0.0 ? p / total : 0.0;
    } else {
      pmf.clear();
    }
    add_case(check_enumeration(
                 contributions, [&](const Visit& visit) { small.enumerate(batch, i, visit); },
                 config.K, pmf),
             out);
  }
  const bool biased = out.expectation_failures > 0;
  out.result = biased ? "biased" : "consistent";
  out.reason = fmt::format(
      "{} of {} camera samples at M = {}, K = {}, N = {}, rounds = {}: E over {} enumerated "
      "sequences of reservoir choices (every reservoir a sample's estimate reads, every outcome) "
      "{} connect-to-all (largest error {:.2g} of the scale); {} support violations (f != 0, "
      "never chosen){}",
      biased ? out.expectation_failures : out.cases, out.cases, out.M, out.K,
      config.rounds > 0 ? config.neighbours : 0, config.rounds, out.sequences,
      biased ? "misses" : "equals", out.max_scaled_error, out.support_violations,
      config.rounds == 0
          ? fmt::format("; largest |E[count_j] - K w_j / Σ w| = {:.2g}", out.max_multiplicity_error)
          : "");
  return out;
}

}  // namespace

ExactCheck exact_check(const RunPlan& plan, std::uint64_t seed) {
  ExactCheck out;
  if (const auto* reservoirs = dynamic_cast<const ReservoirEstimator*>(plan.made_estimator.get())) {
    return exact_check_reservoir(*reservoirs, plan, seed);
  }
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
    add_case(check_case(small.step(), small.pool_view(pools, scratch, i)), out);
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
