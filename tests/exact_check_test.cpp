// The draw schemes, their enumeration, and the exact check of the resampling step.
#include "harness/verify/exact_check.h"

#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>
#include <map>

#include "estimators/draw_scheme.h"
#include "harness/plan/plan.h"
#include "test_support.h"

namespace pcbench {
namespace {

const std::vector<double> kPmf = {0.05, 0.0, 0.3, 0.15, 0.25, 0.25};
const DrawScheme kSchemes[] = {DrawScheme::kIndependent, DrawScheme::kStratified,
                               DrawScheme::kSystematic, DrawScheme::kWithoutReplacement};

// Probabilities of all enumerated sequences sum to 1; the honest schemes draw each j K P_j
// times in expectation, and draws without replacement do not (on a non-uniform P).
TEST(DrawSchemeEnumeration, ProbabilitiesSumToOneAndMultiplicitiesAreKP) {
  constexpr std::uint32_t kK = 3;
  for (DrawScheme scheme : kSchemes) {
    double total = 0.0;
    std::vector<double> counts(kPmf.size(), 0.0);
    enumerate_draws(scheme, kPmf, kK, [&](double p, std::span<const std::uint32_t> draws) {
      total += p;
      for (std::uint32_t j : draws) counts[j] += p;
    });
    EXPECT_NEAR(total, 1.0, 1e-14) << to_string(scheme);
    double worst = 0.0;
    for (std::size_t j = 0; j < kPmf.size(); ++j) {
      worst = std::max(worst, std::fabs(counts[j] - kK * kPmf[j]));
    }
    if (scheme == DrawScheme::kWithoutReplacement) {
      EXPECT_GT(worst, 0.05) << "inclusion probabilities are not K P";
    } else {
      EXPECT_LT(worst, 1e-14) << to_string(scheme);
    }
  }
}

// The sampler and the enumeration describe the same procedure: 100000 sampled sequences follow
// the enumerated distribution (chi-square over sequences, budget 1e-6 per scheme, fixed seed).
TEST(DrawSchemeEnumeration, SampledSequencesFollowTheEnumeration) {
  constexpr std::uint32_t kK = 3;
  constexpr int kDraws = 100000;
  for (DrawScheme scheme : kSchemes) {
    std::map<std::vector<std::uint32_t>, double> expected;
    enumerate_draws(scheme, kPmf, kK, [&](double p, std::span<const std::uint32_t> draws) {
      expected[std::vector<std::uint32_t>(draws.begin(), draws.end())] += p;
    });
    std::map<std::vector<std::uint32_t>, double> seen;
    DiscreteSampler sampler;
    std::vector<std::uint32_t> draws;
    for (int i = 0; i < kDraws; ++i) {
      RandomStream rng({.key = 77, .sample = static_cast<std::uint32_t>(i)});
      draw_indices(scheme, kPmf, kK, DiscreteSamplerKind::kCdf, sampler, rng, draws);
      ASSERT_TRUE(expected.count(draws)) << to_string(scheme) << ": a sequence never enumerated";
      seen[draws] += 1.0;
    }
    double statistic = 0.0;
    for (const auto& [sequence, p] : expected) {
      const double e = p * kDraws;
      const double o = seen.count(sequence) ? seen[sequence] : 0.0;
      statistic += (o - e) * (o - e) / e;
    }
    const boost::math::chi_squared chi2(static_cast<double>(expected.size() - 1));
    EXPECT_GT(boost::math::cdf(boost::math::complement(chi2, statistic)), 1e-6)
        << to_string(scheme);
  }
}

RunPlan plan_for(const std::string& estimator, const std::string& integrand,
                 std::map<std::string, std::vector<std::string>> params = {}) {
  return plan_runs({GridRequest{.estimators = {estimator},
                                .integrands = {integrand},
                                .params = std::move(params),
                                .where = "test"}},
                   {})[0];
}

// Every negative control fails the exact check on its declared integrand, in milliseconds.
TEST(ExactCheck, CatchesEveryNegativeControl) {
  int controls = 0;
  for (const EstimatorEntry& entry : estimator_registry()) {
    if (!entry.biased) continue;
    ++controls;
    ASSERT_TRUE(entry.declared.has_value()) << entry.name;
    std::map<std::string, std::vector<std::string>> params;
    for (const auto& [k, v] : entry.declared->integrand_params) params[k] = {v};
    const ExactCheck check =
        exact_check(plan_for(entry.name, entry.declared->integrand, params), 1);
    EXPECT_EQ(check.result, "biased") << entry.name << ": " << check.reason;
    EXPECT_GT(check.expectation_failures, 0u) << entry.name;
  }
  EXPECT_GE(controls, 7);
}

// Severity 0 removes each control's flaw (ctl-cached-visibility keeps cells of width 1/65536,
// which the check may or may not hit): the check must then pass.
TEST(ExactCheck, ControlsAtSeverityZeroPass) {
  for (const EstimatorEntry& entry : estimator_registry()) {
    if (!entry.biased || entry.name == "ctl-cached-visibility") continue;
    const ExactCheck check =
        exact_check(plan_for(entry.name, entry.declared->integrand, {{"severity", {"0"}}}), 1);
    EXPECT_EQ(check.result, "consistent") << entry.name << ": " << check.reason;
  }
}

// Every honest configuration passes, with multiplicities K P_j and no support violation.
TEST(ExactCheck, PassesEveryHonestConfiguration) {
  const std::vector<RunPlan> plans = plan_runs(
      {GridRequest{.estimators = {"plain", "vc-all", "lvc", "pcbpt"},
                   .integrands = {"genz-oscillatory", "blocker", "linear-emitter"},
                   .params = {{"draws", {"independent", "stratified", "systematic"}},
                              {"importance", {"approx", "f", "uniform", "cached", "adversarial"}},
                              {"pool", {"fresh", "shared"}}},
                   .where = "test"}},
      {});
  ASSERT_GT(plans.size(), 100u);
  for (const RunPlan& plan : plans) {
    const ExactCheck check = exact_check(plan, 3);
    EXPECT_EQ(check.result, "consistent")
        << plan.estimator->name << " " << plan.where << ": " << check.reason;
    EXPECT_EQ(check.support_violations, 0u);
    EXPECT_LT(check.max_multiplicity_error, 1e-12);
  }
}

// ris and restir pass at every target, weighting and round count, on a signed integrand, a
// non-uniform density and visibility (every reservoir choice enumerated).
TEST(ExactCheck, PassesEveryHonestReservoirConfiguration) {
  const std::vector<std::string> integrands = {"genz-oscillatory", "blocker", "linear-emitter"};
  const std::vector<RunPlan> plans =
      plan_runs({GridRequest{.estimators = {"ris"},
                             .integrands = integrands,
                             .params = {{"K", {"1", "3"}},
                                        {"target", {"approx", "f", "uniform"}},
                                        {"pool", {"fresh", "shared"}}},
                             .where = "test"},
                 GridRequest{.estimators = {"restir"},
                             .integrands = integrands,
                             .params = {{"N", {"1", "2"}},
                                        {"rounds", {"1", "2"}},
                                        {"target", {"approx", "f", "uniform"}},
                                        {"weights", {"balance", "pairwise", "count"}}},
                             .where = "test"}},
                {});
  ASSERT_EQ(plans.size(), 36u + 108u);
  for (const RunPlan& plan : plans) {
    const ExactCheck check = exact_check(plan, 3);
    EXPECT_EQ(check.result, "consistent")
        << plan.estimator->name << " " << plan.id << ": " << check.reason;
    EXPECT_EQ(check.support_violations, 0u);
    EXPECT_LT(check.max_multiplicity_error, 1e-12);
  }
}

}  // namespace
}  // namespace pcbench
