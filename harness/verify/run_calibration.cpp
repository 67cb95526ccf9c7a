#include "harness/verify/run_calibration.h"

#include <fmt/format.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "base/errors.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/verify/rounding_bound.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What one seed's run leaves behind.
struct SeedOutcome {
  double p_value = kNaN;
  double test_stderr = kNaN;
  std::vector<ReplicateResult> replicates;   // kept only where the power curve needs them
  double sample_roundings = kTermRoundings;  // of the run (rounding_bound.h), for the power curve
};

// Runs `plan` with seeds first_seed .. first_seed + count - 1, in parallel over seeds (each into
// its own slot, so the order of completion changes nothing); keeps the replicates of the first
// `keep` seeds.
std::vector<SeedOutcome> run_seeds(const RunPlan& plan, const Reference& reference,
                                   std::uint64_t first_seed, std::uint32_t count,
                                   std::uint32_t keep, const std::atomic<bool>* interrupted) {
  std::vector<SeedOutcome> outcomes(count);
  tbb::parallel_for(std::uint32_t{0}, count, [&](std::uint32_t i) {
    const std::uint64_t seed = first_seed + i;
    RunResult run = execute_run(plan, {.seed = seed, .interrupted = interrupted});
    if (run.status == RunStatus::kNotRun) throw CalibrationInterrupted();
    if (run.status != RunStatus::kOk) {
      throw std::runtime_error(fmt::format("calibration: {} on {} with seed {} did not finish: {}",
                                           plan.estimator->name, plan.integrand->name, seed,
                                           run.error));
    }
    SeedOutcome& out = outcomes[i];
    out.sample_roundings = sample_roundings(run.counters);
    const Verdict verdict =
        test_against_reference(run.replicates, reference, "consistent", out.sample_roundings);
    out.p_value = verdict.p_value;
    out.test_stderr = verdict.test_stderr;
    if (i < keep) {
      for (ReplicateResult& rep : run.replicates) rep.largest.clear();
      out.replicates = std::move(run.replicates);
    }
  });
  return outcomes;
}

// KS and binomial tests of a row's p-values; fills everything but the names.
void test_row(CalibrationRow& row, const CalibrationOptions& options) {
  row.seeds = static_cast<std::uint32_t>(row.p_values.size());
  row.ks = ks_uniform(row.p_values);
  row.false_alarms = static_cast<std::uint64_t>(std::count_if(
      row.p_values.begin(), row.p_values.end(), [&](double p) { return p <= options.test_alpha; }));
  row.expected_false_alarms = static_cast<double>(row.p_values.size()) * options.test_alpha;
  row.binomial_p_value =
      binomial_test_p_value(row.false_alarms, row.p_values.size(), options.test_alpha);
  row.pass =
      row.ks.p_value >= options.pass_threshold && row.binomial_p_value >= options.pass_threshold;
}

double normal_power(double ncp, double alpha) {
  const boost::math::normal normal;
  const double z = boost::math::quantile(normal, 1.0 - alpha / 2.0);
  return boost::math::cdf(normal, std::fabs(ncp) - z) +
         boost::math::cdf(normal, -std::fabs(ncp) - z);
}

void validate(const CalibrationOptions& options) {
  const std::string where = "calibration";
  if (options.estimators.empty()) throw InputError(where + ": no estimator given");
  std::set<std::string> seen;
  for (const std::string& name : options.estimators) {
    if (!seen.insert(name).second) {
      throw InputError(fmt::format("{}: estimator '{}' is listed twice", where, name));
    }
  }
  if (options.seeds == 0) throw InputError(where + ": seeds must be at least 1");
  if (options.replicates < 2) throw InputError(where + ": replicates must be at least 2");
  if (options.first_seed >
      std::numeric_limits<std::uint64_t>::max() - std::max(options.seeds, options.power_seeds)) {
    throw InputError(where + ": first_seed + seeds overflows");
  }
  if (!(options.test_alpha > 0.0 && options.test_alpha < 1.0)) {
    throw InputError(
        fmt::format("{}: test_alpha must be in (0, 1), not {}", where, options.test_alpha));
  }
  if (!(options.pass_threshold > 0.0 && options.pass_threshold <= 1.0)) {
    throw InputError(
        fmt::format("{}: pass_threshold must be in (0, 1], not {}", where, options.pass_threshold));
  }
  if (!options.injected_relative_bias.empty()) {
    if (options.power_seeds == 0) throw InputError(where + ": power_seeds must be at least 1");
    for (double delta : options.injected_relative_bias) {
      if (!std::isfinite(delta)) {
        throw InputError(fmt::format("{}: injected relative bias {} is not finite", where, delta));
      }
    }
  }
}

double elapsed_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The calibration's runs: one grid with every estimator (and the power curve's), so that a key
// of `params` only has to be read by one of them, as in a suite.
struct CalibrationPlans {
  std::vector<std::string> names;  // options.estimators, then the power estimator if not among them
  std::vector<RunPlan> plans;
  bool with_power = false;
  bool power_reuses = false;  // the power estimator is calibrated too: its runs serve both

  const RunPlan& of(const std::string& name) const {
    for (const RunPlan& plan : plans) {
      if (plan.estimator->name == name) return plan;
    }
    throw std::logic_error("calibration: no plan for estimator " + name);
  }
};

CalibrationPlans plan_calibration(const CalibrationOptions& options) {
  CalibrationPlans out;
  out.with_power = !options.injected_relative_bias.empty();
  out.names = options.estimators;
  out.power_reuses =
      std::find(out.names.begin(), out.names.end(), options.power_estimator) != out.names.end();
  if (out.with_power && !out.power_reuses) out.names.push_back(options.power_estimator);
  GridRequest grid{.estimators = out.names,
                   .integrands = {options.integrand},
                   .samples = options.samples,
                   .replicates = options.replicates,
                   .where = "calibration"};
  for (const auto& [key, value] : options.params) grid.params[key] = {value};
  out.plans = plan_runs({grid}, {.samples = options.samples, .replicates = options.replicates});
  return out;
}

// The integrand's reference, if the calibration can use it. A reference with an uncertainty of
// its own has one error shared by every seed: the seeds' p-values would not be independent. A
// numerical reference whose error is negligible by its own account (uncertainty 0) is as good as
// exact.
Reference usable_reference(const RunPlan& plan, const CalibrationOptions& options,
                           bool with_power) {
  Reference reference = plan.made_integrand->reference();
  const bool usable = reference.kind == ReferenceKind::kExact ||
                      (reference.kind == ReferenceKind::kNumerical && reference.uncertainty == 0.0);
  if (!usable) {
    throw InputError(fmt::format(
        "calibration: integrand '{}' needs an exact reference (it has kind {}, uncertainty {}): "
        "a reference's own error is shared by every seed, so the p-values would not be "
        "independent",
        options.integrand, to_string(reference.kind), reference.uncertainty));
  }
  if (with_power && reference.value == 0.0) {
    throw InputError(fmt::format(
        "calibration: the reference of '{}' is 0, so a relative bias injects nothing; choose "
        "another integrand or no power curve",
        options.integrand));
  }
  if (plan.integrand->non_negative()) reference.magnitude = std::fabs(reference.value);
  return reference;
}

// The size row of one estimator from its first `options.seeds` outcomes.
CalibrationRow size_row(const RunPlan& plan, const std::vector<SeedOutcome>& outcomes,
                        const CalibrationOptions& options, double scale) {
  CalibrationRow row;
  row.estimator = plan.estimator->name;
  row.biased = plan.estimator->biased;
  row.run_id = plan.id;
  double rel_stderr_sum = 0.0;
  for (std::uint32_t i = 0; i < options.seeds; ++i) {
    row.p_values.push_back(outcomes[i].p_value);
    rel_stderr_sum += outcomes[i].test_stderr / scale;
  }
  row.mean_rel_stderr = rel_stderr_sum / static_cast<double>(options.seeds);
  test_row(row, options);
  return row;
}

// All rows' p-values together (independent: runs of different estimators use separate streams).
CalibrationRow pooled_row(const std::vector<CalibrationRow>& rows,
                          const CalibrationOptions& options) {
  CalibrationRow pooled;
  pooled.estimator = "pooled";
  double rel_stderr_sum = 0.0;
  for (const CalibrationRow& row : rows) {
    pooled.p_values.insert(pooled.p_values.end(), row.p_values.begin(), row.p_values.end());
    rel_stderr_sum += row.mean_rel_stderr;
  }
  pooled.mean_rel_stderr = rel_stderr_sum / static_cast<double>(rows.size());
  test_row(pooled, options);
  return pooled;
}

// One point of the power curve: the power seeds' runs with δ |I| added to every replicate
// estimate, tested again, against the power the measured standard error predicts.
PowerPoint power_point(double delta, const std::vector<SeedOutcome>& outcomes,
                       const Reference& reference, double power_stderr,
                       const CalibrationOptions& options) {
  PowerPoint point;
  point.relative_bias = delta;
  point.bias = delta * std::fabs(reference.value);
  point.seeds = static_cast<std::uint32_t>(outcomes.size());
  for (const SeedOutcome& outcome : outcomes) {
    std::vector<ReplicateResult> shifted = outcome.replicates;
    for (ReplicateResult& rep : shifted) rep.estimate += point.bias;
    const Verdict v =
        test_against_reference(shifted, reference, "biased", outcome.sample_roundings);
    if (v.p_value <= options.test_alpha) ++point.detections;
  }
  point.detection_rate = static_cast<double>(point.detections) / point.seeds;
  const ProportionInterval ci = wilson_interval(point.detections, point.seeds, 0.95);
  point.wilson_low = ci.low;
  point.wilson_high = ci.high;
  if (power_stderr > 0.0) {
    const double ncp = point.bias / power_stderr;
    const double dof = static_cast<double>(options.replicates) - 1.0;
    point.predicted_power = noncentral_t_power(ncp, dof, options.test_alpha);
    point.predicted_power_normal = normal_power(ncp, options.test_alpha);
  } else {  // every replicate gave the same number: the test is exact
    point.predicted_power = point.predicted_power_normal = point.bias != 0.0 ? 1.0 : 0.0;
  }
  return point;
}

// Root mean square of the test's standard error over the outcomes: sqrt of the mean of se²,
// which estimates the true standard error without the downward bias of the mean of se.
double rms_stderr(const std::vector<SeedOutcome>& outcomes) {
  double se2_sum = 0.0;
  for (const SeedOutcome& outcome : outcomes) se2_sum += outcome.test_stderr * outcome.test_stderr;
  return std::sqrt(se2_sum / static_cast<double>(outcomes.size()));
}

}  // namespace

CalibrationResult calibrate(const CalibrationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  validate(options);
  CalibrationResult result;
  result.options = options;
  const CalibrationPlans plans = plan_calibration(options);
  const Reference reference = usable_reference(plans.plans.at(0), options, plans.with_power);
  result.reference = reference.value;

  // Size: every estimator over `seeds` seeds (the power estimator over power_seeds more if needed).
  std::vector<SeedOutcome> power_outcomes;
  for (const std::string& name : plans.names) {
    const RunPlan& plan = plans.of(name);
    const bool is_power = plans.with_power && name == options.power_estimator;
    const bool calibrated = name != options.power_estimator || plans.power_reuses;
    const std::uint32_t count =
        calibrated ? std::max(options.seeds, is_power ? options.power_seeds : options.seeds)
                   : options.power_seeds;
    std::vector<SeedOutcome> outcomes =
        run_seeds(plan, reference, options.first_seed, count, is_power ? options.power_seeds : 0,
                  options.interrupted);
    if (calibrated) {
      result.rows.push_back(size_row(plan, outcomes, options, std::fabs(reference.value)));
    }
    if (is_power) {
      result.power_run_id = plan.id;
      outcomes.resize(options.power_seeds);
      power_outcomes = std::move(outcomes);
    }
  }
  result.pooled = pooled_row(result.rows, options);
  result.pass = result.pooled.pass && std::all_of(result.rows.begin(), result.rows.end(),
                                                  [](const CalibrationRow& r) { return r.pass; });

  if (plans.with_power) {
    result.power_stderr = rms_stderr(power_outcomes);
    for (const double delta : options.injected_relative_bias) {
      result.power.push_back(
          power_point(delta, power_outcomes, reference, result.power_stderr, options));
    }
  }
  result.wall_seconds = elapsed_since(start);
  return result;
}

}  // namespace pcbench
