#include "harness/commands/calibration.h"

#include <fmt/format.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <set>
#include <stdexcept>

#include "base/errors.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/session/publish.h"
#include "harness/session/report.h"
#include "harness/verify/rounding_bound.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using Json = nlohmann::ordered_json;

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

}  // namespace

CalibrationResult calibrate(const CalibrationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  validate(options);
  CalibrationResult result;
  result.options = options;

  // One grid with every estimator (and the power curve's): a key of `params` then only has to be
  // read by one of them, as in a suite.
  const bool with_power = !options.injected_relative_bias.empty();
  std::vector<std::string> names = options.estimators;
  const bool power_reuses =
      std::find(names.begin(), names.end(), options.power_estimator) != names.end();
  if (with_power && !power_reuses) names.push_back(options.power_estimator);
  GridRequest grid{.estimators = names,
                   .integrands = {options.integrand},
                   .samples = options.samples,
                   .replicates = options.replicates,
                   .where = "calibration"};
  for (const auto& [key, value] : options.params) grid.params[key] = {value};
  const std::vector<RunPlan> plans =
      plan_runs({grid}, {.samples = options.samples, .replicates = options.replicates});
  const auto plan_of = [&](const std::string& name) -> const RunPlan& {
    for (const RunPlan& plan : plans) {
      if (plan.estimator->name == name) return plan;
    }
    throw std::logic_error("calibration: no plan for estimator " + name);
  };

  Reference reference = plans.at(0).made_integrand->reference();
  // A reference with an uncertainty of its own has one error shared by every seed: the seeds'
  // p-values would not be independent. A numerical reference whose error is negligible by its own
  // account (uncertainty 0) is as good as exact.
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
  if (plans.at(0).integrand->non_negative()) reference.magnitude = std::fabs(reference.value);
  result.reference = reference.value;
  const double scale = std::fabs(reference.value);

  // Size: every estimator over `seeds` seeds (the power estimator over power_seeds more if needed).
  std::vector<SeedOutcome> power_outcomes;
  for (const std::string& name : names) {
    const RunPlan& plan = plan_of(name);
    const bool is_power = with_power && name == options.power_estimator;
    const bool calibrated = name != options.power_estimator || power_reuses;
    const std::uint32_t count =
        calibrated ? std::max(options.seeds, is_power ? options.power_seeds : options.seeds)
                   : options.power_seeds;
    std::vector<SeedOutcome> outcomes =
        run_seeds(plan, reference, options.first_seed, count, is_power ? options.power_seeds : 0,
                  options.interrupted);
    if (calibrated) {
      CalibrationRow row;
      row.estimator = name;
      row.biased = plan.estimator->biased;
      row.run_id = plan.id;
      double rel_stderr_sum = 0.0;
      for (std::uint32_t i = 0; i < options.seeds; ++i) {
        row.p_values.push_back(outcomes[i].p_value);
        rel_stderr_sum += outcomes[i].test_stderr / scale;
      }
      row.mean_rel_stderr = rel_stderr_sum / static_cast<double>(options.seeds);
      test_row(row, options);
      result.rows.push_back(std::move(row));
    }
    if (is_power) {
      result.power_run_id = plan.id;
      outcomes.resize(options.power_seeds);
      power_outcomes = std::move(outcomes);
    }
  }

  result.pooled.estimator = "pooled";
  double rel_stderr_sum = 0.0;
  for (const CalibrationRow& row : result.rows) {
    result.pooled.p_values.insert(result.pooled.p_values.end(), row.p_values.begin(),
                                  row.p_values.end());
    rel_stderr_sum += row.mean_rel_stderr;
  }
  result.pooled.mean_rel_stderr = rel_stderr_sum / static_cast<double>(result.rows.size());
  test_row(result.pooled, options);
  result.pass = result.pooled.pass && std::all_of(result.rows.begin(), result.rows.end(),
                                                  [](const CalibrationRow& r) { return r.pass; });

  // Power: the same runs with δ |I| added to every replicate estimate.
  if (with_power) {
    double se2_sum = 0.0;
    for (const SeedOutcome& outcome : power_outcomes) {
      se2_sum += outcome.test_stderr * outcome.test_stderr;
    }
    result.power_stderr = std::sqrt(se2_sum / static_cast<double>(power_outcomes.size()));
    const double dof = static_cast<double>(options.replicates) - 1.0;
    for (const double delta : options.injected_relative_bias) {
      PowerPoint point;
      point.relative_bias = delta;
      point.bias = delta * scale;
      point.seeds = static_cast<std::uint32_t>(power_outcomes.size());
      for (const SeedOutcome& outcome : power_outcomes) {
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
      if (result.power_stderr > 0.0) {
        const double ncp = point.bias / result.power_stderr;
        point.predicted_power = noncentral_t_power(ncp, dof, options.test_alpha);
        point.predicted_power_normal = normal_power(ncp, options.test_alpha);
      } else {  // every replicate gave the same number: the test is exact
        point.predicted_power = point.predicted_power_normal = point.bias != 0.0 ? 1.0 : 0.0;
      }
      result.power.push_back(point);
    }
  }
  result.wall_seconds = elapsed_since(start);
  return result;
}

namespace {

Json number(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

Json row_json(const CalibrationRow& row, bool with_run) {
  Json j = Json::object();
  j["estimator"] = row.estimator;
  if (with_run) {
    j["biased"] = row.biased;
    j["run_id"] = row.run_id;
  }
  j["seeds"] = row.seeds;
  j["ks_statistic"] = number(row.ks.statistic);
  j["ks_p_value"] = number(row.ks.p_value);
  j["false_alarms"] = row.false_alarms;
  j["expected_false_alarms"] = number(row.expected_false_alarms);
  j["binomial_p_value"] = number(row.binomial_p_value);
  j["pass"] = row.pass;
  j["mean_rel_stderr"] = number(row.mean_rel_stderr);
  if (with_run) {
    Json p = Json::array();
    for (double value : row.p_values) p.push_back(number(value));
    j["p_values"] = std::move(p);
  }
  return j;
}

}  // namespace

nlohmann::ordered_json calibration_json(const CalibrationResult& result) {
  const CalibrationOptions& o = result.options;
  Json params = Json::object();
  for (const auto& [key, value] : o.params) params[key] = value;
  Json rows = Json::array();
  for (const CalibrationRow& row : result.rows) rows.push_back(row_json(row, true));
  Json j = Json::object();
  j["integrand"] = o.integrand;
  j["params"] = std::move(params);
  j["reference"] = number(result.reference);
  j["samples"] = o.samples;
  j["replicates"] = o.replicates;
  j["seeds"] = o.seeds;
  j["first_seed"] = o.first_seed;
  j["test_alpha"] = o.test_alpha;
  j["pass_threshold"] = o.pass_threshold;
  j["pass"] = result.pass;
  j["estimators"] = std::move(rows);
  j["pooled"] = row_json(result.pooled, false);
  if (result.power.empty()) {
    j["power"] = nullptr;
  } else {
    Json points = Json::array();
    for (const PowerPoint& p : result.power) {
      points.push_back(Json{{"relative_bias", number(p.relative_bias)},
                            {"bias", number(p.bias)},
                            {"seeds", p.seeds},
                            {"detections", p.detections},
                            {"detection_rate", number(p.detection_rate)},
                            {"wilson_low", number(p.wilson_low)},
                            {"wilson_high", number(p.wilson_high)},
                            {"predicted_power", number(p.predicted_power)},
                            {"predicted_power_normal", number(p.predicted_power_normal)}});
    }
    j["power"] = Json{{"estimator", o.power_estimator},
                      {"run_id", result.power_run_id},
                      {"seeds", o.power_seeds},
                      {"stderr", number(result.power_stderr)},
                      {"rel_stderr", number(result.power_stderr / std::fabs(result.reference))},
                      {"dof", o.replicates - 1},
                      {"points", std::move(points)}};
  }
  j["wall_seconds"] = number(result.wall_seconds);
  return j;
}

void print_calibration(const CalibrationResult& result, std::ostream& out) {
  const CalibrationOptions& o = result.options;
  out << fmt::format(
      "Calibration on {}: seeds {}..{}, {} replicates x {} samples; single tests at alpha = {}; a "
      "row passes when its KS and binomial p >= {}\n",
      o.integrand, o.first_seed, o.first_seed + o.seeds - 1, o.replicates, o.samples, o.test_alpha,
      o.pass_threshold);
  out << fmt::format("{:<24} {:>6} {:>7} {:>9} {:>13} {:>9} {:>11}  {}\n", "estimator", "seeds",
                     "KS D", "KS p", "false alarms", "expected", "binomial p", "pass");
  const auto print_row = [&](const CalibrationRow& row) {
    const std::string name = row.biased ? row.estimator + " (biased)" : row.estimator;
    out << fmt::format("{:<24} {:>6} {:>7.4f} {:>9.3g} {:>13} {:>9.1f} {:>11.3g}  {}\n", name,
                       row.seeds, row.ks.statistic, row.ks.p_value,
                       fmt::format("{} / {}", row.false_alarms, row.seeds),
                       row.expected_false_alarms, row.binomial_p_value, row.pass ? "yes" : "NO");
  };
  for (const CalibrationRow& row : result.rows) print_row(row);
  print_row(result.pooled);
  out << fmt::format("calibration: {}\n", result.pass ? "pass" : "FAIL");
  if (result.power.empty()) return;
  out << fmt::format(
      "\nPower curve ({}, {} seeds): bias delta x |I| added to every replicate estimate, I = "
      "{:.6g},"
      " standard error {:.3g} ({:.3g} relative)\n",
      o.power_estimator, o.power_seeds, result.reference, result.power_stderr,
      result.power_stderr / std::fabs(result.reference));
  out << fmt::format("{:>8} {:>7} {:>12} {:>9} {:>17} {:>11} {:>11}\n", "delta", "bias/se",
                     "detected", "rate", "95% Wilson", "predicted", "normal appr");
  for (const PowerPoint& p : result.power) {
    out << fmt::format("{:>8.0e} {:>7.2f} {:>12} {:>9.3f} {:>17} {:>11.3f} {:>11.3f}\n",
                       p.relative_bias, p.bias / result.power_stderr,
                       fmt::format("{} / {}", p.detections, p.seeds), p.detection_rate,
                       fmt::format("[{:.3f}, {:.3f}]", p.wilson_low, p.wilson_high),
                       p.predicted_power, p.predicted_power_normal);
  }
}

int publish_self_test(const char* suite, const ReportSections& sections, bool pass,
                      std::uint64_t first_seed, const SessionOptions& session, std::ostream& out,
                      std::ostream& err) {
  // The report's suite is the self-test, its seed the first of the seeds it ran.
  SessionOptions self_test = session;
  self_test.suite_name = suite;
  self_test.seed = first_seed;
  if (!publish_report(self_test, sections, out, err)) return kExitRunFailed;
  return pass ? kExitOk : kExitVerdictDiffers;
}

int run_calibration(const CalibrationOptions& options, const SessionOptions& session,
                    std::ostream& out, std::ostream& err) {
  return run_self_test(
      "calibration", options.first_seed, session, out, err, [&] { return calibrate(options); },
      print_calibration,
      [](const CalibrationResult& result, ReportSections& sections) {
        sections.calibration = nlohmann::json(calibration_json(result));
      });
}

}  // namespace pcbench
