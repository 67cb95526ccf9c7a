// The exact variance of plain, vc-all and lvc, derived for any integrand from three moments, and
// checked against the spread of replicates. Correlated random streams (a pool reusing camera
// numbers, neighbouring samples sharing a stream) leave the mean right but change the variance;
// these tests see that.
//
// With sampling densities p(x), p(y), h(y) = ∫ f(x, y) dx, S2 = ∫∫ f² / (p(x) p(y)),
// H2 = ∫ h² / p(y), I = ∫∫ f, a fresh pool of M paths and K uniform draws with replacement, the
// per-sample variances are
//   vc-all:  (S2 - H2) / M + H2 - I²                      (plain is M = 1)
//   lvc:     (1/K)(1 - 1/M)(S2 - H2) + (S2 - H2) / M + H2 - I²
// (condition on y and the pool: the K draws add (1/K) × the pool's spread, whose mean over pools
// is (1 - 1/M) Var_x f; the pool mean adds Var_x f / M; then average over y.)
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <functional>

#include "base/tally.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "integrands/blocker.h"
#include "integrands/door.h"
#include "integrands/genz_continuous.h"
#include "integrands/genz_corner_peak.h"
#include "integrands/genz_product_peak.h"
#include "integrands/registry.h"

namespace pcbench {
namespace {

struct Moments {
  double integral;       // I
  double square;         // S2 = ∫∫ f² / (p(x) p(y))
  double inner_squared;  // H2 = ∫ (∫ f dx)² / p(y) dy
};

// f and the sampling densities of a 1 + 1 dimensional integrand.
struct Kernel {
  std::function<double(double x, double y)> f;
  std::function<double(double)> light_pdf = [](double) { return 1.0; };
  std::function<double(double)> camera_pdf = [](double) { return 1.0; };
  // Where f(·, y) jumps (visibility), so that quadrature integrates smooth pieces.
  std::function<std::vector<double>(double y)> jumps = [](double) { return std::vector<double>{}; };
};

// Flatland visibility through a line at height t: the segment (x, 0) -> (y, h) crosses it at
// c = x + t (y - x), so it crosses [lo, hi] for x between (lo - t y)/(1 - t) and (hi - t y)/(1 -
// t).
std::vector<double> crossing_jumps(double y, double t, double lo, double hi) {
  return {(lo - t * y) / (1 - t), (hi - t * y) / (1 - t)};
}

// The kernel of a registered point model at its default parameters (plus `overrides`), with its
// densities where it samples non-uniformly.
Kernel with_jumps(Kernel k, std::function<std::vector<double>(double)> jumps) {
  k.jumps = std::move(jumps);
  return k;
}

template <typename Model>
Kernel model_kernel(const ParamText& overrides = {}) {
  const auto model = std::make_shared<Model>(resolve_params(Model::params(), overrides, "test"));
  Kernel k{.f = [model](double x, double y) { return model->f(&x, &y); }};
  if constexpr (requires(const double* t) { model->light_pdf(t); }) {
    k.light_pdf = [model](double x) { return model->light_pdf(&x); };
  }
  if constexpr (requires(const double* t) { model->camera_pdf(t); }) {
    k.camera_pdf = [model](double y) { return model->camera_pdf(&y); };
  }
  return k;
}

// The outer integrals have kinks (where a visibility interval meets the domain's edge): a
// 1e-9 tolerance keeps their bisection short, and is far below the tests' ~3% resolution.
double integrate(const std::function<double(double)>& g) {
  return boost::math::quadrature::gauss_kronrod<double, 61>::integrate(g, 0.0, 1.0, 12, 1e-9);
}

// Nested adaptive Gauss–Kronrod on [0,1]²: independent of how pcbench computes references.
// ∫_0^1 g, split at the points of `jumps` inside (0, 1).
double integrate_pieces(const std::function<double(double)>& g, std::vector<double> jumps) {
  jumps.push_back(0.0);
  jumps.push_back(1.0);
  std::sort(jumps.begin(), jumps.end());
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < jumps.size(); ++i) {
    const double a = std::clamp(jumps[i], 0.0, 1.0), b = std::clamp(jumps[i + 1], 0.0, 1.0);
    if (b > a) {
      total += boost::math::quadrature::gauss_kronrod<double, 61>::integrate(g, a, b, 12, 1e-11);
    }
  }
  return total;
}

Moments moments(const Kernel& k) {
  Moments m{};
  const auto inner = [&](double y) {
    return integrate_pieces([&](double x) { return k.f(x, y); }, k.jumps(y));
  };
  m.integral = integrate(inner);
  m.square = integrate([&](double y) {
    return integrate_pieces([&](double x) { return k.f(x, y) * k.f(x, y) / k.light_pdf(x); },
                            k.jumps(y)) /
           k.camera_pdf(y);
  });
  m.inner_squared = integrate([&](double y) {
    const double h = inner(y);
    return h * h / k.camera_pdf(y);
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
  const auto kernel = [](std::function<double(double, double)> f) { return Kernel{.f = f}; };
  const std::vector<Case> cases = {
      // Written out by hand, independent of the library's models:
      {"genz-gaussian", {{"center", {"0.3"}}}, kernel([](double x, double y) {
         return std::exp(-16.0 * ((x - 0.3) * (x - 0.3) + (y - 0.3) * (y - 0.3)));
       })},
      {"genz-oscillatory", {}, kernel([](double x, double y) {  // not separable
         return std::cos(2 * M_PI * 0.25 + 3.0 * (x + y));
       })},
      // Most of the variance on the light side, so that the pool size shows in the variance.
      {"expr",
       {{"f", {"exp(-16 * (x0 - 0.3)^2) * (1 + 0.1 * y0)"}}},
       kernel([](double x, double y) {
         return std::exp(-16 * (x - 0.3) * (x - 0.3)) * (1 + 0.1 * y);
       })},
      // The models' own f and densities (their values are checked against quadrature in
      // catalog_test.cpp): the Genz peaks, a non-uniform density, and two transport kernels
      // with visibility (the door opened wide enough for the quadrature to see it).
      {"genz-product-peak", {}, model_kernel<GenzProductPeak>()},
      {"genz-corner-peak", {}, model_kernel<GenzCornerPeak>()},
      {"genz-continuous",
       {},
       with_jumps(model_kernel<GenzContinuous>(),
                  [](double) {
                    return std::vector<double>{0.4};  // the kink at c
                  })},
      {"blocker",
       {},
       with_jumps(model_kernel<Blocker>(),
                  [](double y) {
                    return crossing_jumps(y, 0.5, 0.6 - 0.2, 0.6 + 0.2);  // strip at the defaults
                  })},
      {"door",
       {{"gap", {"0.05"}}},
       with_jumps(model_kernel<Door>({{"gap", "0.05"}}),
                  [](double y) {
                    return crossing_jumps(y, 0.5, 0.4 - 0.025,
                                          0.4 + 0.025);  // opening at the defaults
                  })},
  };
  struct Config {
    std::string estimator;
    std::map<std::string, std::vector<std::string>> params;
    double M, K;
  };
  const std::vector<Config> configs = {{"plain", {}, 1, 1},
                                       {"vc-all", {{"M", {"4"}}}, 4, 1},
                                       {"vc-all", {{"M", {"32"}}}, 32, 1},
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
      // The kernel here is the integrand the run uses.
      if (reference.kind == ReferenceKind::kExact) {
        ASSERT_NEAR(reference.value, m.integral, 1e-8 * std::fabs(m.integral)) << c.integrand;
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
