#include "harness/verify/efficiency_ratio.h"

#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <vector>

#include "harness/run/tally.h"

namespace pcbench {

namespace {

// Mean and variance (n - 1 in the denominator) with the harness's own accumulation.
Tally tally_of(std::span<const double> values) {
  Tally tally;
  for (std::size_t i = 0; i < values.size(); ++i) tally.add(values[i], i);
  return tally;
}

// Each factor's share of the miss probability (Bonferroni over the two).
constexpr double kFactorMiss = (1.0 - kEfficiencyRatioLevel) / 2.0;

}  // namespace

EfficiencyRatio efficiency_ratio(std::span<const double> estimates_a, std::span<const double> cpu_a,
                                 std::span<const double> estimates_b,
                                 std::span<const double> cpu_b) {
  EfficiencyRatio out;
  out.pairs = static_cast<std::uint32_t>(std::min(cpu_a.size(), cpu_b.size()));
  if (estimates_a.size() < 2 || estimates_b.size() < 2 || out.pairs < 2) return out;
  const double var_a = tally_of(estimates_a).variance();
  const double var_b = tally_of(estimates_b).variance();
  std::vector<double> log_cost;  // log(c_a,r / c_b,r)
  for (std::uint32_t r = 0; r < out.pairs; ++r) {
    if (cpu_a[r] <= 0.0 || cpu_b[r] <= 0.0) return out;
    log_cost.push_back(std::log(cpu_a[r] / cpu_b[r]));
  }
  if (!(var_a > 0.0) || !(var_b > 0.0) || !std::isfinite(var_a) || !std::isfinite(var_b)) {
    return out;
  }

  // (s²_a/s²_b) / (σ²_a/σ²_b) ~ F(ν_a, ν_b): the interval of σ²_a/σ²_b divides by its quantiles.
  const boost::math::fisher_f f(static_cast<double>(estimates_a.size() - 1),
                                static_cast<double>(estimates_b.size() - 1));
  out.variance_ratio = var_a / var_b;
  out.variance_low = out.variance_ratio / boost::math::quantile(f, 1.0 - kFactorMiss / 2.0);
  out.variance_high = out.variance_ratio / boost::math::quantile(f, kFactorMiss / 2.0);

  const Tally cost = tally_of(log_cost);
  const double mean = cost.mean();
  const double se = std::sqrt(cost.variance() / static_cast<double>(log_cost.size()));
  const double t = boost::math::quantile(
      boost::math::students_t(static_cast<double>(log_cost.size() - 1)), 1.0 - kFactorMiss / 2.0);
  out.cost_ratio = std::exp(mean);
  out.cost_low = std::exp(mean - t * se);
  out.cost_high = std::exp(mean + t * se);

  out.ratio = out.variance_ratio * out.cost_ratio;
  out.low = out.variance_low * out.cost_low;
  out.high = out.variance_high * out.cost_high;
  out.valid = true;
  return out;
}

}  // namespace pcbench
