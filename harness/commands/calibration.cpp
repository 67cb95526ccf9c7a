#include "harness/commands/calibration.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <ostream>

#include "base/json_number.h"
#include "harness/session/publish.h"

namespace pcbench {
namespace {

using Json = nlohmann::ordered_json;

Json row_json(const CalibrationRow& row, bool with_run) {
  Json j = Json::object();
  j["estimator"] = row.estimator;
  if (with_run) {
    j["biased"] = row.biased;
    j["run_id"] = row.run_id;
  }
  j["seeds"] = row.seeds;
  j["ks_statistic"] = finite_or_null(row.ks.statistic);
  j["ks_p_value"] = finite_or_null(row.ks.p_value);
  j["false_alarms"] = row.false_alarms;
  j["expected_false_alarms"] = finite_or_null(row.expected_false_alarms);
  j["binomial_p_value"] = finite_or_null(row.binomial_p_value);
  j["pass"] = row.pass;
  j["mean_rel_stderr"] = finite_or_null(row.mean_rel_stderr);
  if (with_run) {
    Json p = Json::array();
    for (double value : row.p_values) p.push_back(finite_or_null(value));
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
  j["reference"] = finite_or_null(result.reference);
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
      points.push_back(Json{{"relative_bias", finite_or_null(p.relative_bias)},
                            {"bias", finite_or_null(p.bias)},
                            {"seeds", p.seeds},
                            {"detections", p.detections},
                            {"detection_rate", finite_or_null(p.detection_rate)},
                            {"wilson_low", finite_or_null(p.wilson_low)},
                            {"wilson_high", finite_or_null(p.wilson_high)},
                            {"predicted_power", finite_or_null(p.predicted_power)},
                            {"predicted_power_normal", finite_or_null(p.predicted_power_normal)}});
    }
    j["power"] =
        Json{{"estimator", o.power_estimator},
             {"run_id", result.power_run_id},
             {"seeds", o.power_seeds},
             {"stderr", finite_or_null(result.power_stderr)},
             {"rel_stderr", finite_or_null(result.power_stderr / std::fabs(result.reference))},
             {"dof", o.replicates - 1},
             {"points", std::move(points)}};
  }
  j["wall_seconds"] = finite_or_null(result.wall_seconds);
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
