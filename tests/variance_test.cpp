// The exact variance of plain, vc-all and lvc, derived for any integrand from three moments, and
// checked against the spread of replicates. Correlated random streams (a pool reusing camera
// numbers, neighbouring samples sharing a stream) leave the mean right but change the variance;
// these tests see that.
//
// With uniform densities, h(y) = ∫ f(x, y) dx, S2 = ∫∫ f², H2 = ∫ h², I = ∫∫ f, a fresh pool of
// M paths and K uniform draws with replacement, the per-sample variances are
//   vc-all:  (S2 - H2) / M + H2 - I²                      (plain is M = 1)
//   lvc:     (1/K)(1 - 1/M)(S2 - H2) + (S2 - H2) / M + H2 - I²
// (condition on y and the pool: the K draws add (1/K) × the pool's spread, whose mean over pools
// is (1 - 1/M) Var_x f; the pool mean adds Var_x f / M; then average over y.)
#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <functional>

#include "harness/plan.h"
#include "harness/runner.h"
#include "harness/tally.h"
#include "integrands/registry.h"

namespace pcbench {
namespace {

struct Moments {
  double integral;       // I
  double square;         // S2 = ∫∫ f²
  double inner_squared;  // H2 = ∫ (∫ f dx)² dy
};

using Kernel = std::function<double(double x, double y)>;

double integrate(const std::function<double(double)>& g) {
  return boost::math::quadrature::gauss_kronrod<double, 61>::integrate(g, 0.0, 1.0, 15, 1e-13);
}

// Nested adaptive Gauss–Kronrod on [0,1]²: independent of how pcbench computes references.
Moments moments(const Kernel& f) {
  Moments m{};
  const auto inner = [&](double y) { return integrate([&](double x) { return f(x, y); }); };
  m.integral = integrate(inner);
  m.square =
      integrate([&](double y) { return integrate([&](double x) { return f(x, y) * f(x, y); }); });
  m.inner_squared = integrate([&](double y) {
    const double h = inner(y);
    return h * h;
  });
  return m;
}

double exact_variance(const Moments& m, const std::string& estimator, double M, double K) {
  const double within = m.square - m.inner_squared;
  const double base = within / M + m.inner_squared - m.integral * m.integral;
  if (estimator == "lvc") return base + (1.0 / K) * (1.0 - 1.0 / M) * within;
  return base;
}

struct Case {
  std::string integrand;
  std::map<std::string, std::vector<std::string>> integrand_params;
  Kernel f;
};

// (R - 1) s² / σ² ~ χ²(R - 1) for the across-replicate variance s² of replicate means.
double variance_p_value(const RunResult& result, double per_sample_variance, double samples) {
  Tally spread;
  for (std::size_t r = 0; r < result.replicates.size(); ++r) {
    spread.add(result.replicates[r].estimate, r);
  }
  const double dof = static_cast<double>(result.replicates.size() - 1);
  const double statistic = dof * spread.variance() / (per_sample_variance / samples);
  const boost::math::chi_squared chi2(dof);
  return 2 * std::min(boost::math::cdf(chi2, statistic),
                      boost::math::cdf(boost::math::complement(chi2, statistic)));
}

TEST(VarianceExact, PlainVcAllAndLvcMatchTheirDerivedVariance) {
  constexpr double kSharpness = 4.0;
  const std::vector<Case> cases = {
      {"genz-gaussian",
       {{"center", {"0.3"}}},
       [](double x, double y) {
         return std::exp(-kSharpness * kSharpness *
                         ((x - 0.3) * (x - 0.3) + (y - 0.3) * (y - 0.3)));
       }},
      {"genz-oscillatory",
       {},  // defaults: s = 3, c = 0.25 — not separable
       [](double x, double y) { return std::cos(2 * M_PI * 0.25 + 3.0 * (x + y)); }},
      // Most of the variance on the light side, so that the pool size shows in the variance.
      {"expr",
       {{"f", {"exp(-16 * (x0 - 0.3)^2) * (1 + 0.1 * y0)"}}},
       [](double x, double y) { return std::exp(-16 * (x - 0.3) * (x - 0.3)) * (1 + 0.1 * y); }},
  };
  struct Config {
    std::string estimator;
    std::map<std::string, std::vector<std::string>> params;
    double M, K;
  };
  const std::vector<Config> configs = {{"plain", {}, 1, 1},
                                       {"vc-all", {{"M", {"4"}}}, 4, 1},
                                       {"vc-all", {{"M", {"32"}}}, 32, 1},
                                       {"lvc", {{"M", {"16"}}, {"K", {"1"}}}, 16, 1},
                                       {"lvc", {{"M", {"16"}}, {"K", {"4"}}}, 16, 4}};
  // Budget: 1e-4 family-wise over all cells (Bonferroni), fixed seed.
  const double alpha = 1e-4 / static_cast<double>(cases.size() * configs.size());
  // Many short replicates: the variance of a variance estimate falls as 2 / R, so R = 2000 puts
  // a 25% error in the variance (vc-all with 24 paths counted as 32) at about 8 sigma.
  constexpr std::uint64_t kSamples = 400;
  constexpr std::uint32_t kReplicates = 2000;
  for (const Case& c : cases) {
    const Moments m = moments(c.f);
    for (const Config& config : configs) {
      auto params = c.integrand_params;
      params.insert(config.params.begin(), config.params.end());
      GridRequest grid{.estimators = {config.estimator},
                       .integrands = {c.integrand},
                       .params = params,
                       .samples = kSamples,
                       .replicates = kReplicates,
                       .where = "test"};
      const RunPlan plan = plan_runs({grid}, {})[0];
      const Reference reference = plan.made_integrand->reference();
      if (reference.kind == ReferenceKind::kExact) {
        ASSERT_NEAR(reference.value, m.integral, 1e-10) << c.integrand;
      }
      const RunResult result = execute_run(plan, {.seed = 77});
      const double sigma2 = exact_variance(m, config.estimator, config.M, config.K);
      EXPECT_GT(variance_p_value(result, sigma2, kSamples), alpha)
          << config.estimator << " M=" << config.M << " K=" << config.K << " on " << c.integrand
          << ": exact per-sample variance " << sigma2;
    }
  }
}

}  // namespace
}  // namespace pcbench
