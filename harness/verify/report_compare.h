// `pcbench compare A.json B.json`: did a change alter an estimator? Pairs the runs of two reports
// by id and tests each pair's replicate estimates for equal means (Welch's two-sample t-test),
// with Holm–Bonferroni over the pairs at a family-wise alpha (docs/reference/INTERFACE.md, Report
// and Determinism).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "harness/plan/estimates_file.h"
#include "harness/verify/statistics.h"

namespace pcbench {

struct Comparison {
  std::string a = {};  // run id in report A
  std::string b = {};  // run id in report B (the same id: runs are paired by id)
  std::string estimator = {};
  std::string integrand = {};
  std::string test = "welch";
  double statistic = 0.0;             // (mean_a - mean_b) / sqrt(stderr_a² + stderr_b²)
  double dof = 0.0;                   // Welch–Satterthwaite
  double p_value = 1.0;               // raw, two-sided
  double p_adjusted = 1.0;            // Holm over the compared pairs
  double alpha = kDefaultAlpha;       // the family-wise threshold p_adjusted is compared with
  std::string result = "consistent";  // consistent (no difference found) | biased (differs) |
                                      // inconclusive (the test is undefined)
  std::string expect = "consistent";
  std::string reason = {};
  double mean_a = 0.0;
  double mean_b = 0.0;
  double stderr_a = 0.0;  // standard error of mean_a, across replicates
  double stderr_b = 0.0;
  std::size_t replicates_a = 0;
  std::size_t replicates_b = 0;
  // The |mean_a - mean_b| this test detects with 80% power at the Bonferroni share alpha / m: a
  // "consistent" result rules out differences about this large, not smaller ones.
  double min_detectable_difference = 0.0;
  // Scene block tests (harness/verify/block_pyramid.h): each scale of the pyramid, finest first,
  // and every block×channel test's within-comparison adjusted p, kept for the maps of the blocks
  // that differ (comparison_json writes only those, once the family has decided).
  struct Scale {
    std::uint32_t block = 0, columns = 0, rows = 0, tests = 0;
    // Bright block×channel tests (block mean >= 10% of the image mean of the channel).
    std::uint32_t bright_tests = 0;
    // The largest detectable bias relative to a bright block's mean, at the share of alpha
    // `alpha_share` = alpha / (m × L × n_s) that decides (m the session family's tested verdicts,
    // L the scales, n_s this scale's tests).
    double relative_mdb = 0.0;
    // The median of the same over the bright blocks (the worst is one block, often a dim one).
    double median_relative_mdb = 0.0;
    double alpha_share = 0.0;
    double min_p_adjusted = 1.0;  // within the comparison
    std::optional<double> required_mdb = {};
  };
  std::vector<Scale> scales = {};
  // Scene block tests on the replicate differences of two runs with shared random streams.
  bool paired = false;
  struct BlockP {
    std::uint32_t scale = 0, x = 0, y = 0, channel = 0;
    double p_adjusted = 1.0;
  };
  std::vector<BlockP> block_p_values = {};
};

// The blocks of a block comparison that differ, at every scale: those whose within-comparison
// adjusted p, scaled by the family's factor for this comparison (p_adjusted / p_value), is <=
// alpha. A biased comparison has at least its smallest-p block; any other result has none.
std::vector<Comparison::BlockP> blocks_differing(const Comparison& c);

// A run id present in both reports but not compared, and why (a run not ok, < 2 replicates).
struct UncomparedRun {
  std::string id = {};
  std::string reason = {};
};

struct ComparisonOutcome {
  std::vector<Comparison> comparisons;      // in report A's run order
  std::vector<std::string> only_in_a;       // run ids, in A's order
  std::vector<std::string> only_in_b;       // run ids, in B's order
  std::vector<UncomparedRun> not_compared;  // paired, but not both ok with >= 2 replicates
  std::vector<std::string> warnings;        // e.g. both reports used the same seed
  // Every comparison's result equals its expectation (the exit status is 1 otherwise).
  bool as_expected() const;
};

// The figures of a two-sample test (statistic, dof, both means and standard errors) into `c`,
// its p-values and counts left as they are.
void set_test_figures(Comparison& c, const TwoSampleTest& test);

// Compares two reports already read; `name_a` and `name_b` name them in warnings and reasons.
// alpha must be in (0, 1] (InputError otherwise).
// The figures of a two-sample test between runs a and b, before any family correction.
Comparison comparison_from(const TwoSampleTest& test, std::string a, std::string b,
                           std::size_t replicates_a, std::size_t replicates_b);

ComparisonOutcome compare_reports(const ReportData& a, const ReportData& b,
                                  double alpha = kDefaultAlpha, std::string_view name_a = "A",
                                  std::string_view name_b = "B");

// Reads both reports (read_report: InputError for a missing file, bad JSON, schema_version other
// than 1, ...) and compares them.
ComparisonOutcome compare_report_files(const std::filesystem::path& a,
                                       const std::filesystem::path& b,
                                       double alpha = kDefaultAlpha);

// One entry of a report's `comparisons[]` (results/report.schema.json, $defs/comparison): the
// required fields, then the optional ones; non-finite figures are null.
nlohmann::ordered_json comparison_json(const Comparison& comparison);
nlohmann::ordered_json comparisons_json(const std::vector<Comparison>& comparisons);

// The whole outcome: {comparisons, only_in_a, only_in_b, not_compared: [{id, reason}], warnings}.
nlohmann::ordered_json outcome_json(const ComparisonOutcome& outcome);

}  // namespace pcbench
