// Calibration self-test of the verifier: does the test of a run against its reference
// (test_against_reference) mean what it says?
//
//  1. Size. For an unbiased estimator, the raw two-sided p-value of one run is Uniform(0, 1) when
//     the test is right. Each estimator runs on one integrand with an exact reference for
//     `seeds` seeds; the p-values are tested against U(0, 1) (Kolmogorov–Smirnov, ks_uniform) and
//     the number of false alarms (p <= test_alpha) against Binomial(seeds, test_alpha) (exact,
//     binomial_test_p_value). Per estimator and pooled over the estimators.
//  2. Power. A bias of relative size δ is injected into the runs of one estimator: δ × |I| is
//     added to every replicate estimate (I the reference), which is in distribution exactly a
//     biased estimator with that offset. The detection rate at level test_alpha over
//     `power_seeds` seeds is set against the power predicted from the measured standard error.
//
// Cheap by design: the power curve reuses the calibration runs of its estimator (an injection is
// an offset of numbers already computed). Deterministic: the numbers depend only on the options
// (seeds run in parallel, each into its own slot; a run is bitwise the same for any thread count).
#pragma once

#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/params.h"
#include "harness/run/diagnostics.h"  // KsResult
#include "harness/verify/statistics.h"

namespace pcbench {

struct CalibrationOptions {
  // The estimators to calibrate, each with its default parameters (M, K, ...) unless `params`
  // sets them. They should be unbiased: a negative control here makes its row fail, which is how
  // the tests show the self-test can fail.
  std::vector<std::string> estimators = {"plain", "vc-all", "lvc", "pcbpt"};
  // The integrand; it must have an exact reference, or a numerical one with uncertainty 0 (a
  // reference's own error would be shared by every seed, so the p-values would not be
  // independent).
  std::string integrand = "genz-gaussian";
  // Parameters as text, key -> value; a key goes to the estimators and integrand that read it
  // (as in a suite grid), and a key nobody reads is an InputError. Empty: all defaults.
  ParamText params = {};
  // Camera samples per replicate. 1000 keeps the default self-test at ~6 s of CPU (~3 s on 2
  // cores); replicate means of 1000 samples of a bounded integrand are close enough to normal
  // for the t test's p-values to be uniform at what 200 seeds can resolve.
  std::uint64_t samples = 1000;
  std::uint32_t replicates = 16;  // per run; the t test has replicates - 1 degrees of freedom
  std::uint32_t seeds = 200;      // runs per estimator: seeds first_seed .. first_seed + seeds - 1
  std::uint64_t first_seed = 1;
  // The level of each single test (no family correction): a false alarm, or a detection in the
  // power curve, is p <= test_alpha (the verifier's rejection rule).
  double test_alpha = 0.05;
  // A row passes when its KS and binomial p-values are both >= pass_threshold. This is the error
  // budget of the self-test itself: with the defaults, 4 estimators + the pooled row, × 2 tests,
  // at 1e-3 each, a correct verifier fails the self-test with probability <= 10 × 1e-3 = 1%
  // (Bonferroni).
  double pass_threshold = 1e-3;
  // Ctrl-C: the runs stop, and calibrate throws CalibrationInterrupted (a self-test over part of
  // its seeds would be another test, so nothing is reported).
  const std::atomic<bool>* interrupted = nullptr;
  // The power curve: the estimator it injects bias into (its calibration runs are reused when it
  // is among `estimators`), the injected relative biases δ, and the seeds (the first power_seeds
  // of the calibration seeds). An empty list of δ skips the power curve.
  std::string power_estimator = "plain";
  std::vector<double> injected_relative_bias = {1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1};
  std::uint32_t power_seeds = 100;
};

// The size test of one estimator (or of all pooled).
struct CalibrationRow {
  std::string estimator = {};  // "pooled" for the pooled row
  bool biased = false;         // a negative control (registry's `biased`): expected to fail
  std::string run_id = {};     // the plan's id (empty for the pooled row)
  std::uint32_t seeds = 0;
  std::vector<double> p_values = {};   // raw two-sided p-value per seed, in seed order
  KsResult ks = {};                    // of p_values against U(0, 1)
  std::uint64_t false_alarms = 0;      // p <= test_alpha
  double expected_false_alarms = 0.0;  // seeds × test_alpha
  double binomial_p_value = 1.0;       // of false_alarms against Binomial(seeds, test_alpha)
  bool pass = false;                   // both p-values >= pass_threshold
  double mean_rel_stderr = 0.0;        // mean over seeds of the test's standard error / |I|
};

// One point of the power curve.
struct PowerPoint {
  double relative_bias = 0.0;  // δ
  double bias = 0.0;           // δ × |I|, added to every replicate estimate
  std::uint32_t seeds = 0;
  std::uint32_t detections = 0;  // p <= test_alpha
  double detection_rate = 0.0;
  double wilson_low = 0.0;  // 95% Wilson score interval of the detection rate
  double wilson_high = 0.0;
  // Power at test_alpha for a bias of `bias` with the measured standard error (see
  // CalibrationResult::power_stderr): P(|T| > t_{1-α/2, ν}) for T noncentral t with ν =
  // replicates - 1 and noncentrality bias / power_stderr, exact for normal replicate estimates.
  double predicted_power = 0.0;
  // The normal approximation Φ(b/se - z_{1-α/2}) + Φ(-b/se - z_{1-α/2}), b = |bias|: slightly
  // optimistic at small replicate counts (it ignores the t quantile and the spread of se).
  double predicted_power_normal = 0.0;
};

struct CalibrationResult {
  CalibrationOptions options = {};
  double reference = 0.0;                 // I, the integrand's exact reference
  std::vector<CalibrationRow> rows = {};  // one per estimator, in the order of options.estimators
  CalibrationRow pooled = {};  // all rows' p-values together (independent: runs of different
                               // estimators use separate random streams)
  bool pass = false;           // every row and the pooled row pass
  // The power curve (empty when options.injected_relative_bias is).
  std::string power_run_id = {};
  // Root mean square over the power seeds of the test's standard error: sqrt of the mean of se²,
  // which estimates the true standard error without the downward bias of the mean of se.
  double power_stderr = 0.0;
  std::vector<PowerPoint> power = {};
  double wall_seconds = 0.0;  // of calibrate() (the only number that is not deterministic)
};

// Runs the self-test. Throws InputError for bad options (unknown names, an integrand without an
// exact reference, a power curve on a zero reference, fewer than 2 replicates, no seeds) and
// std::runtime_error if a run fails or produces non-finite samples.
CalibrationResult calibrate(const CalibrationOptions& options);

struct CalibrationInterrupted : std::runtime_error {
  CalibrationInterrupted() : std::runtime_error("calibration interrupted") {}
};

}  // namespace pcbench
