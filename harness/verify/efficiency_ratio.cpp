#include "harness/verify/efficiency_ratio.h"

#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <vector>

#include "base/tally.h"
#include "harness/run/interleaved_runs.h"

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

nlohmann::json efficiency_ratios_json(const std::vector<RunRecord>& records, bool interleaved) {
  std::vector<const RunPlan*> plans;
  for (const RunRecord& r : records) plans.push_back(r.plan);
  nlohmann::json out = nlohmann::json::array();
  for (const std::vector<std::size_t>& group : same_integrand_groups(plans)) {
    std::vector<const RunRecord*> finished;
    for (std::size_t i : group) {
      const RunRecord& r = records[i];
      if (r.result.status == RunStatus::kOk && !r.plan->render) finished.push_back(&r);
    }
    const auto baseline = std::find_if(finished.begin(), finished.end(), [](const RunRecord* r) {
      return !r->plan->estimator->biased;
    });
    if (baseline == finished.end()) continue;
    const auto columns = [](const RunRecord& r) {
      std::pair<std::vector<double>, std::vector<double>> c;
      for (const ReplicateResult& rep : r.result.replicates) {
        c.first.push_back(rep.estimate);
        c.second.push_back(rep.cpu_seconds);
      }
      return c;
    };
    const auto [estimates_a, cpu_a] = columns(**baseline);
    for (const RunRecord* b : finished) {
      if (b == *baseline) continue;
      const auto [estimates_b, cpu_b] = columns(*b);
      const EfficiencyRatio e = efficiency_ratio(estimates_a, cpu_a, estimates_b, cpu_b);
      if (!e.valid) continue;
      out.push_back(
          {{"integrand", b->plan->integrand->name},
           {"a", (*baseline)->plan->id},
           {"b", b->plan->id},
           {"estimator", b->plan->estimator->name + " vs " + (*baseline)->plan->estimator->name},
           {"ratio", e.ratio},
           {"low", e.low},
           {"high", e.high},
           {"level", kEfficiencyRatioLevel},
           {"variance_ratio", e.variance_ratio},
           {"variance_low", e.variance_low},
           {"variance_high", e.variance_high},
           {"cost_ratio", e.cost_ratio},
           {"cost_low", e.cost_low},
           {"cost_high", e.cost_high},
           {"pairs", e.pairs},
           {"interleaved", interleaved}});
    }
  }
  return out;
}

}  // namespace pcbench
