#include "harness/commands/calibration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "base/errors.h"

namespace pcbench {
namespace {

// The calibration runs of the CI tests: small (256 samples × 16 replicates) but 200 seeds, so the
// KS and binomial tests see the whole distribution of the p-values.
CalibrationOptions small_options(std::vector<std::string> estimators) {
  CalibrationOptions options;
  options.estimators = std::move(estimators);
  options.samples = 256;
  options.replicates = 16;
  options.seeds = 200;
  options.first_seed = 1;
  options.injected_relative_bias = {};
  return options;
}

// Two unbiased estimators (the simplest and the most involved) are calibrated: their raw p-values
// are uniform and their false alarms at 0.05 binomial. Error budget: 3 rows (2 estimators and
// the pooled one) × 2 tests at 1e-3 each, so a correct verifier fails here at a random seed with
// probability <= 0.6%; the seed is fixed, so the test is deterministic.
TEST(Calibration, UnbiasedEstimatorsGiveUniformPValues) {
  const CalibrationResult result = calibrate(small_options({"plain", "pcbpt"}));
  ASSERT_EQ(result.rows.size(), 2u);
  std::vector<const CalibrationRow*> rows = {&result.rows[0], &result.rows[1], &result.pooled};
  for (const CalibrationRow* row : rows) {
    EXPECT_GE(row->ks.p_value, 1e-3) << row->estimator;
    EXPECT_GE(row->binomial_p_value, 1e-3) << row->estimator;
    EXPECT_TRUE(row->pass) << row->estimator;
    EXPECT_FALSE(row->biased) << row->estimator;
  }
  EXPECT_EQ(result.pooled.seeds, 400u);
  EXPECT_TRUE(result.pass);
}

// The self-test can fail: a negative control whose bias is 1–2 standard errors of one run shifts
// its p-values towards 0, and KS rejects uniformity overwhelmingly. (ctl-wrong-count divides by
// M - s instead of M: a relative bias s / (M - s) exactly.)
TEST(Calibration, PlantedMiscalibrationIsCaught) {
  CalibrationOptions options = small_options({"ctl-wrong-count"});
  constexpr double kM = 16.0;
  constexpr double kSeverity = 0.3;
  options.params = {{"M", "16"}, {"severity", "0.3"}};
  const CalibrationResult result = calibrate(options);
  const CalibrationRow& row = result.rows.at(0);
  // The bias is small: 1 to 2 standard errors of a run's mean (measured: ~1.5).
  const double bias_in_stderrs = kSeverity / (kM - kSeverity) / row.mean_rel_stderr;
  EXPECT_GT(bias_in_stderrs, 1.0);
  EXPECT_LT(bias_in_stderrs, 2.0);
  EXPECT_TRUE(row.biased);
  EXPECT_LT(row.ks.p_value, 1e-6);
  EXPECT_LT(row.binomial_p_value, 1e-6);
  EXPECT_GT(row.false_alarms, 2 * row.expected_false_alarms);
  EXPECT_FALSE(row.pass);
  EXPECT_FALSE(result.pass);
}

// Checks a power curve against its prediction; shared by the CI and the Full test.
//  - At the largest δ (10 standard errors or more) the predicted power is 1 - O(1e-6): the
//    detection rate must be >= 0.95.
//  - At the smallest δ (a hundredth of a standard error) the predicted power is α (+1e-5): the
//    detections are Binomial(100, α); more than 3α = 15 of 100 has probability 4e-5.
//  - Every point's detection rate has the predicted power inside its 99.9% Wilson interval: 7
//    points at ~1e-3 each, a false failure at a random seed <= ~0.7%.
//  - Monotone-ish: the power of the two-sided test grows with |δ|, but on the same seeds a seed
//    whose t was below -t_crit leaves the rejection region as δ grows; such seeds are ~α/2 of
//    them, so a drop of more than 10 of 100 (P(Bin(100, 0.025) > 10) ≈ 1e-4) is a failure.
void expect_power_curve_matches_prediction(const CalibrationResult& result) {
  const std::vector<PowerPoint>& power = result.power;
  ASSERT_EQ(power.size(), result.options.injected_relative_bias.size());
  ASSERT_GE(power.size(), 2u);
  const double alpha = result.options.test_alpha;
  // The premises of the thresholds below.
  EXPECT_GE(power.back().bias / result.power_stderr, 10.0);
  EXPECT_LE(power.front().bias / result.power_stderr, 0.02);
  EXPECT_GE(power.back().predicted_power, 0.999);
  EXPECT_NEAR(power.front().predicted_power, alpha, 1e-3);

  EXPECT_GE(power.back().detection_rate, 0.95);
  EXPECT_LE(power.front().detection_rate, 3.0 * alpha);
  for (std::size_t i = 0; i < power.size(); ++i) {
    const PowerPoint& p = power[i];
    const ProportionInterval ci = wilson_interval(p.detections, p.seeds, 0.999);
    EXPECT_GE(p.predicted_power, ci.low) << "delta " << p.relative_bias;
    EXPECT_LE(p.predicted_power, ci.high) << "delta " << p.relative_bias;
    EXPECT_GE(p.wilson_low, 0.0);
    EXPECT_LE(p.wilson_low, p.detection_rate);
    EXPECT_GE(p.wilson_high, p.detection_rate);
    EXPECT_LE(p.wilson_high, 1.0);
    // The normal approximation is never below the t prediction (it ignores the t quantile).
    EXPECT_GE(p.predicted_power_normal, p.predicted_power - 1e-12) << "delta " << p.relative_bias;
    if (i > 0) {
      EXPECT_GE(p.predicted_power, power[i - 1].predicted_power);
      EXPECT_GE(p.detection_rate, power[i - 1].detection_rate - 0.1) << "delta " << p.relative_bias;
    }
  }
}

// The power curve of plain at the default budget (1000 samples × 16 replicates: one run's
// relative standard error ≈ 1%), so δ from 1e-4 to 1e-1 spans 0.01 to 10 standard errors.
TEST(CalibrationPower, DetectionRateFollowsThePredictedPower) {
  CalibrationOptions options;
  options.estimators = {"plain"};
  options.first_seed = 1;
  const CalibrationResult result = calibrate(options);
  EXPECT_EQ(result.power.front().seeds, 100u);
  expect_power_curve_matches_prediction(result);
}

// The power curve reuses the calibration runs when its estimator is calibrated, and runs its own
// otherwise: the same seeds give the same curve either way.
TEST(CalibrationPower, SameCurveWhetherOrNotItsEstimatorIsCalibrated) {
  CalibrationOptions options = small_options({"plain"});
  options.seeds = 10;
  options.power_seeds = 20;  // more than seeds: the calibrated runs are extended
  options.injected_relative_bias = {1e-2, 1e-1};
  const CalibrationResult reused = calibrate(options);
  options.estimators = {"lvc"};
  const CalibrationResult separate = calibrate(options);
  ASSERT_EQ(reused.power.size(), 2u);
  ASSERT_EQ(separate.power.size(), 2u);
  EXPECT_EQ(separate.rows.size(), 1u);
  EXPECT_EQ(separate.rows[0].estimator, "lvc");
  EXPECT_EQ(reused.power_stderr, separate.power_stderr);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(reused.power[i].seeds, 20u);
    EXPECT_EQ(reused.power[i].detections, separate.power[i].detections);
  }
  EXPECT_EQ(reused.power_run_id, separate.power_run_id);
}

CalibrationOptions tiny_options() {
  CalibrationOptions options;
  options.estimators = {"plain", "lvc"};
  options.samples = 256;
  options.replicates = 4;
  options.seeds = 20;
  options.power_seeds = 10;
  options.first_seed = 7;
  options.injected_relative_bias = {1e-3, 1e-1};
  return options;
}

nlohmann::ordered_json without_timing(nlohmann::ordered_json j) {
  j.erase("wall_seconds");
  return j;
}

// The same options give the same numbers, bit for bit (seeds run in parallel, each into its own
// slot); another first seed gives other numbers.
TEST(CalibrationDeterminism, SameOptionsSameNumbers) {
  const CalibrationResult a = calibrate(tiny_options());
  const CalibrationResult b = calibrate(tiny_options());
  EXPECT_EQ(a.rows[0].p_values, b.rows[0].p_values);
  EXPECT_EQ(a.rows[1].p_values, b.rows[1].p_values);
  EXPECT_EQ(without_timing(calibration_json(a)).dump(), without_timing(calibration_json(b)).dump());
  std::ostringstream text_a, text_b;
  print_calibration(a, text_a);
  print_calibration(b, text_b);
  EXPECT_EQ(text_a.str(), text_b.str());

  CalibrationOptions shifted = tiny_options();
  shifted.first_seed = 8;
  const CalibrationResult c = calibrate(shifted);
  EXPECT_NE(a.rows[0].p_values, c.rows[0].p_values);
  // Seed s's run is the same whatever the first seed: the shifted series is the original's tail.
  EXPECT_EQ(std::vector<double>(a.rows[0].p_values.begin() + 1, a.rows[0].p_values.end()),
            std::vector<double>(c.rows[0].p_values.begin(), c.rows[0].p_values.end() - 1));
}

nlohmann::json load_schema() {
  std::ifstream in(std::string(PCBENCH_SOURCE_DIR) + "/results/report.schema.json");
  return nlohmann::json::parse(in);
}

// Every field the schema requires is written, and every field written is documented there.
void expect_fields_match(const nlohmann::ordered_json& object, const nlohmann::json& definition,
                         const std::string& where) {
  ASSERT_TRUE(object.is_object()) << where;
  for (const auto& key : definition.at("required")) {
    EXPECT_TRUE(object.contains(key.get<std::string>())) << where << ": missing " << key;
  }
  for (const auto& [key, value] : object.items()) {
    EXPECT_TRUE(definition.at("properties").contains(key)) << where << ": undocumented " << key;
  }
}

TEST(CalibrationJson, HasTheDocumentedFields) {
  const CalibrationResult result = calibrate(tiny_options());
  const nlohmann::ordered_json j = calibration_json(result);
  const nlohmann::json schema = load_schema();
  const nlohmann::json& defs = schema.at("$defs");
  ASSERT_TRUE(schema.at("properties").contains("calibration"));
  const auto& required = schema.at("required");
  EXPECT_EQ(std::find(required.begin(), required.end(), "calibration"), required.end());

  expect_fields_match(j, defs.at("calibration"), "calibration");
  ASSERT_EQ(j.at("estimators").size(), 2u);
  for (const auto& row : j.at("estimators")) {
    expect_fields_match(row, defs.at("calibrationRow"), "calibration/estimators");
    EXPECT_TRUE(row.contains("biased"));
    EXPECT_TRUE(row.contains("run_id"));
    EXPECT_EQ(row.at("p_values").size(), 20u);
  }
  expect_fields_match(j.at("pooled"), defs.at("calibrationRow"), "calibration/pooled");
  expect_fields_match(j.at("power"), defs.at("powerCurve"), "calibration/power");
  ASSERT_EQ(j.at("power").at("points").size(), 2u);
  for (const auto& point : j.at("power").at("points")) {
    expect_fields_match(point, defs.at("powerPoint"), "calibration/power/points");
  }

  EXPECT_EQ(j.at("integrand"), "genz-gaussian");
  EXPECT_EQ(j.at("seeds"), 20);
  EXPECT_EQ(j.at("first_seed"), 7);
  EXPECT_EQ(j.at("estimators")[0].at("estimator"), "plain");
  EXPECT_EQ(j.at("estimators")[1].at("estimator"), "lvc");
  EXPECT_EQ(j.at("estimators")[1].at("run_id").get<std::string>().size(), 16u);
  EXPECT_EQ(j.at("pooled").at("estimator"), "pooled");
  EXPECT_EQ(j.at("pooled").at("seeds"), 40);
  EXPECT_EQ(j.at("pooled").at("false_alarms"),
            result.rows[0].false_alarms + result.rows[1].false_alarms);
  EXPECT_EQ(j.at("pass"), result.pass);
  EXPECT_EQ(j.at("power").at("dof"), 3);
  EXPECT_EQ(j.at("power").at("points")[1].at("relative_bias"), 1e-1);
  EXPECT_EQ(j.at("power").at("points")[1].at("seeds"), 10);

  // Without a power curve, `power` is null; the summary says what it has.
  CalibrationOptions no_power = tiny_options();
  no_power.injected_relative_bias = {};
  const CalibrationResult plain_only = calibrate(no_power);
  EXPECT_TRUE(calibration_json(plain_only).at("power").is_null());
  std::ostringstream text;
  print_calibration(result, text);
  EXPECT_NE(text.str().find("pooled"), std::string::npos);
  EXPECT_NE(text.str().find("Power curve"), std::string::npos);
}

TEST(CalibrationInput, BadOptionsAreInputErrors) {
  CalibrationOptions options = tiny_options();
  options.estimators = {"plain", "plain"};
  EXPECT_THROW(calibrate(options), InputError);
  options = tiny_options();
  options.estimators = {"no-such-estimator"};
  EXPECT_THROW(calibrate(options), InputError);
  options = tiny_options();
  options.integrand = "expr";  // no exact value given: no reference
  options.params = {{"f", "x0 * y0"}};
  EXPECT_THROW(calibrate(options), InputError);
  options = tiny_options();
  options.params = {{"nobody_reads_this", "1"}};
  EXPECT_THROW(calibrate(options), InputError);
  options = tiny_options();
  options.integrand = "expr";  // a zero reference: a relative bias injects nothing
  options.params = {{"f", "x0 - y0"}, {"exact", "0"}};
  EXPECT_THROW(calibrate(options), InputError);
  options = tiny_options();
  options.replicates = 1;
  EXPECT_THROW(calibrate(options), InputError);
  options = tiny_options();
  options.seeds = 0;
  EXPECT_THROW(calibrate(options), InputError);
  options = tiny_options();
  options.test_alpha = 0.0;
  EXPECT_THROW(calibrate(options), InputError);
}

TEST(CalibrationWilson, MatchesTheScoreIntervalFormula) {
  // R: prop.test(5, 100, correct = FALSE)$conf.int
  const ProportionInterval a = wilson_interval(5, 100, 0.95);
  EXPECT_NEAR(a.low, 0.0215437, 1e-6);
  EXPECT_NEAR(a.high, 0.1117505, 1e-6);
  const ProportionInterval b = wilson_interval(0, 10, 0.95);
  EXPECT_EQ(b.low, 0.0);
  EXPECT_NEAR(b.high, 0.2775328, 1e-6);
  const ProportionInterval c = wilson_interval(10, 10, 0.95);
  EXPECT_NEAR(c.low, 0.7224672, 1e-6);
  EXPECT_EQ(c.high, 1.0);
  const ProportionInterval wide = wilson_interval(5, 100, 0.999);
  EXPECT_LT(wide.low, a.low);
  EXPECT_GT(wide.high, a.high);
}

// The self-test with its defaults (4 estimators × 200 seeds × 16 replicates × 1000 samples, the
// power curve of plain over 100 seeds): it passes, and the curve follows its prediction. Error
// budget: 10 tests at 1e-3 (1%) plus the power checks (~0.7%). Prints the summary.
TEST(FullCalibration, DefaultOptionsPass) {
  const CalibrationResult result = calibrate({});
  print_calibration(result, std::cout);
  std::cout << "calibrate() took " << result.wall_seconds << " s\n";
  ASSERT_EQ(result.rows.size(), 4u);
  for (const CalibrationRow& row : result.rows) EXPECT_TRUE(row.pass) << row.estimator;
  EXPECT_TRUE(result.pooled.pass);
  EXPECT_TRUE(result.pass);
  expect_power_curve_matches_prediction(result);
}

}  // namespace
}  // namespace pcbench
