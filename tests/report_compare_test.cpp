#include "harness/verify/report_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "base/errors.h"
#include "base/rng.h"
#include "harness/verify/statistics.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;
using Strings = std::vector<std::string>;
using Values = std::vector<double>;

constexpr const char* kId1 = "0000000000000001";
constexpr const char* kId2 = "0000000000000002";
constexpr const char* kId3 = "0000000000000003";
constexpr const char* kId4 = "0000000000000004";
constexpr const char* kId5 = "0000000000000005";
constexpr const char* kId6 = "0000000000000006";

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// `count` draws of mean + spread × (U - 1/2) × sqrt(12): mean `mean`, standard deviation `spread`.
Values draws(double mean, double spread, std::size_t count, std::uint64_t key) {
  RandomStream stream(StreamId{.key = key});
  Values out;
  for (std::size_t i = 0; i < count; ++i) {
    out.push_back(mean + spread * (stream.uniform() - 0.5) * std::sqrt(12.0));
  }
  return out;
}

// Writes reports A and B into `folder` and compares them.
ComparisonOutcome compare_written(const TemporaryFolder& folder, const nlohmann::json& a,
                                  const nlohmann::json& b, double alpha = kDefaultAlpha) {
  write_text(folder.path() / "a.json", a.dump(2));
  write_text(folder.path() / "b.json", b.dump(2));
  return compare_report_files(folder.path() / "a.json", folder.path() / "b.json", alpha);
}

// ---------------------------------------------------------------------------------------------
// The two-sample test

TEST(ReportCompareWelch, StatisticDofAndPValueMatchAHandComputation) {
  const Values a = {1, 2, 3, 4}, b = {2, 4, 6, 8, 10};
  const TwoSampleTest welch = welch_two_sample(a, b);
  // Means 2.5 and 6; sample variances 5/3 and 10, so squared standard errors 5/12 and 2.
  const double va = 5.0 / 12.0, vb = 2.0;
  EXPECT_DOUBLE_EQ(welch.mean_a, 2.5);
  EXPECT_DOUBLE_EQ(welch.mean_b, 6.0);
  EXPECT_DOUBLE_EQ(welch.stderr_a, std::sqrt(va));
  EXPECT_DOUBLE_EQ(welch.stderr_b, std::sqrt(vb));
  EXPECT_DOUBLE_EQ(welch.statistic, -3.5 / std::sqrt(va + vb));
  EXPECT_DOUBLE_EQ(welch.dof, (va + vb) * (va + vb) / (va * va / 3.0 + vb * vb / 4.0));
  // The same figures computed independently (Python: statistics module, and the t density
  // integrated by Simpson's rule).
  EXPECT_NEAR(welch.statistic, -2.2514363231593695, 1e-12);
  EXPECT_NEAR(welch.dof, 5.520787746170677, 1e-12);
  EXPECT_NEAR(welch.p_value, 0.0691335931923936, 1e-9);
  // Swapping the samples flips the sign only.
  const TwoSampleTest swapped = welch_two_sample(b, a);
  EXPECT_DOUBLE_EQ(swapped.statistic, -welch.statistic);
  EXPECT_DOUBLE_EQ(swapped.p_value, welch.p_value);
}

TEST(ReportCompareWelch, SamplesThatDoNotVaryGiveAnExactAnswer) {
  const TwoSampleTest same = welch_two_sample(Values{2, 2, 2}, Values{2, 2});
  EXPECT_EQ(same.statistic, 0.0);
  EXPECT_EQ(same.p_value, 1.0);
  EXPECT_EQ(same.dof, 3.0);
  const TwoSampleTest different = welch_two_sample(Values{2, 2, 2}, Values{3, 3});
  EXPECT_EQ(different.statistic, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(different.p_value, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Comparing reports

TEST(ReportCompareReports, PairsRunsByIdAndListsTheRest) {
  TemporaryFolder folder;
  const nlohmann::json a =
      small_report({small_report_run(kId1, {1, 2, 3}), small_report_run(kId2, {4, 5, 6}),
                    small_report_run(kId3, {}, "error"), small_report_run(kId4, {1}),
                    small_report_run(kId6, {1, 2})},
                   1);
  const nlohmann::json b =
      small_report({small_report_run(kId5, {1, 2}), small_report_run(kId2, {4, 5, 6.5}),
                    small_report_run(kId1, {1, 2, 3.5}, "ok", "plain", "genz-gaussian"),
                    small_report_run(kId3, {1, 2}), small_report_run(kId4, {1, 2})},
                   2);
  const ComparisonOutcome outcome = compare_written(folder, a, b);
  ASSERT_EQ(outcome.comparisons.size(), 2u);
  // In A's order, each against the run of B with the same id.
  EXPECT_EQ(outcome.comparisons[0].a, kId1);
  EXPECT_EQ(outcome.comparisons[0].b, kId1);
  EXPECT_EQ(outcome.comparisons[0].mean_b, 6.5 / 3.0);
  EXPECT_EQ(outcome.comparisons[1].a, kId2);
  EXPECT_EQ(outcome.comparisons[1].mean_b, 15.5 / 3.0);
  EXPECT_EQ(outcome.comparisons[0].estimator, "plain");
  EXPECT_EQ(outcome.comparisons[0].integrand, "genz-gaussian");
  EXPECT_EQ(outcome.comparisons[0].replicates_a, 3u);
  // Runs in one report only are listed, not errors.
  EXPECT_EQ(outcome.only_in_a, Strings{kId6});
  EXPECT_EQ(outcome.only_in_b, Strings{kId5});
  // Paired runs that cannot be tested say why.
  ASSERT_EQ(outcome.not_compared.size(), 2u);
  EXPECT_EQ(outcome.not_compared[0].id, kId3);
  EXPECT_TRUE(contains(outcome.not_compared[0].reason, "status error in "))
      << outcome.not_compared[0].reason;
  EXPECT_TRUE(contains(outcome.not_compared[0].reason, "a.json (it failed)"));
  EXPECT_EQ(outcome.not_compared[1].id, kId4);
  EXPECT_TRUE(contains(outcome.not_compared[1].reason, "1 replicate(s) in "));
  EXPECT_TRUE(outcome.warnings.empty());  // seeds 1 and 2
}

TEST(ReportCompareReports, AClearDifferenceIsFlagged) {
  TemporaryFolder folder;
  // A 2% shift with 1% spread over 32 replicates: about 8 standard errors.
  const nlohmann::json a = small_report({small_report_run(kId1, draws(1.0, 0.01, 32, 1)),
                                         small_report_run(kId2, draws(5.0, 0.1, 32, 2))},
                                        1);
  const nlohmann::json b = small_report({small_report_run(kId1, draws(1.02, 0.01, 32, 3)),
                                         small_report_run(kId2, draws(5.0, 0.1, 32, 4))},
                                        2);
  const ComparisonOutcome outcome = compare_written(folder, a, b);
  ASSERT_EQ(outcome.comparisons.size(), 2u);
  const Comparison& changed = outcome.comparisons[0];
  EXPECT_EQ(changed.test, "welch");
  EXPECT_EQ(changed.result, "biased");
  EXPECT_EQ(changed.expect, "consistent");
  EXPECT_LT(changed.statistic, -5.0);  // A's mean is the smaller
  EXPECT_LE(changed.p_adjusted, kDefaultAlpha);
  EXPECT_TRUE(contains(changed.reason, "the means differ")) << changed.reason;
  EXPECT_EQ(outcome.comparisons[1].result, "consistent");
  EXPECT_FALSE(outcome.as_expected());
}

TEST(ReportCompareReports, ReplicatesFromOneDistributionAreNotFlagged) {
  TemporaryFolder folder;
  std::vector<nlohmann::json> runs_a, runs_b;
  const Strings ids = {kId1, kId2, kId3, kId4, kId5};
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const double mean = 1.0 + static_cast<double>(i);
    runs_a.push_back(small_report_run(ids[i], draws(mean, 0.05, 32, 10 + i)));
    runs_b.push_back(small_report_run(ids[i], draws(mean, 0.05, 32, 20 + i)));
  }
  const ComparisonOutcome outcome =
      compare_written(folder, small_report(runs_a, 1), small_report(runs_b, 2));
  ASSERT_EQ(outcome.comparisons.size(), ids.size());
  for (const Comparison& c : outcome.comparisons) {
    SCOPED_TRACE(c.a);
    EXPECT_EQ(c.result, "consistent") << c.reason;
    EXPECT_GT(c.p_adjusted, kDefaultAlpha);
    EXPECT_TRUE(contains(c.reason, "no difference detected")) << c.reason;
    // The difference this could have found: a few standard errors of the difference.
    const double se = std::hypot(c.stderr_a, c.stderr_b);
    EXPECT_GT(c.min_detectable_difference, 3.0 * se);
    EXPECT_LT(c.min_detectable_difference, 6.0 * se);
  }
  EXPECT_TRUE(outcome.as_expected());
}

TEST(ReportCompareReports, HolmAdjustsAcrossTheComparisons) {
  TemporaryFolder folder;
  // Shifts of 0, 1, 2 and 6 standard errors of the difference (spread 0.1, 16 replicates each).
  const double se = 0.1 * std::sqrt(2.0 / 16.0);
  const Values shifts = {0.0, 1.0, 2.0, 6.0};
  const Strings ids = {kId1, kId2, kId3, kId4};
  std::vector<nlohmann::json> runs_a, runs_b;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    runs_a.push_back(small_report_run(ids[i], draws(1.0, 0.1, 16, 30 + i)));
    runs_b.push_back(small_report_run(ids[i], draws(1.0 + shifts[i] * se, 0.1, 16, 40 + i)));
  }
  const double alpha = 0.05;
  const ComparisonOutcome outcome =
      compare_written(folder, small_report(runs_a, 1), small_report(runs_b, 2), alpha);
  ASSERT_EQ(outcome.comparisons.size(), 4u);
  Values p;
  for (const Comparison& c : outcome.comparisons) p.push_back(c.p_value);
  const Values expected = holm_adjusted(p);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Comparison& c = outcome.comparisons[i];
    EXPECT_EQ(c.p_adjusted, expected[i]);
    EXPECT_GE(c.p_adjusted, c.p_value);
    EXPECT_EQ(c.alpha, alpha);  // the family-wise threshold p_adjusted is compared with
    EXPECT_EQ(c.result, c.p_adjusted <= alpha ? "biased" : "consistent");
  }
  // Holm by hand: the smallest p is multiplied by 4, the next by 3, ... and never decreases.
  std::vector<std::size_t> order = {0, 1, 2, 3};
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return p[i] < p[j]; });
  double running = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    running = std::max(running, std::min(1.0, p[order[k]] * static_cast<double>(4 - k)));
    EXPECT_DOUBLE_EQ(outcome.comparisons[order[k]].p_adjusted, running);
  }
  EXPECT_EQ(outcome.comparisons[3].result, "biased");  // the shift of 6 standard errors
}

TEST(ReportCompareReports, SameSeedIsWarnedAbout) {
  TemporaryFolder folder;
  const nlohmann::json a = small_report({small_report_run(kId1, {1, 2, 3})}, 7);
  const nlohmann::json b = small_report({small_report_run(kId1, {1, 2, 3})}, 7);
  const ComparisonOutcome same = compare_written(folder, a, b);
  ASSERT_EQ(same.warnings.size(), 1u);
  EXPECT_TRUE(contains(same.warnings[0], "both used seed 7")) << same.warnings[0];
  EXPECT_TRUE(contains(same.warnings[0], "not independent")) << same.warnings[0];
  EXPECT_TRUE(contains(same.warnings[0], (folder.path() / "a.json").string()));
  // Identical replicates: no difference, and the test still runs.
  ASSERT_EQ(same.comparisons.size(), 1u);
  EXPECT_EQ(same.comparisons[0].statistic, 0.0);
  EXPECT_EQ(same.comparisons[0].result, "consistent");

  const nlohmann::json other_seed = small_report({small_report_run(kId1, {1, 2, 3})}, 8);
  EXPECT_TRUE(compare_written(folder, a, other_seed).warnings.empty());
}

TEST(ReportCompareReports, BadSchemaVersionIsRejected) {
  TemporaryFolder folder;
  const nlohmann::json a = small_report({small_report_run(kId1, {1, 2, 3})});
  nlohmann::json b = a;
  b["schema_version"] = 2;
  try {
    compare_written(folder, a, b);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_TRUE(message.starts_with((folder.path() / "b.json").string() + ": /schema_version: "))
        << message;
    EXPECT_TRUE(contains(message, "pcbench reads reports of schema_version 1; this one has 2"));
  }
  b.erase("schema_version");
  EXPECT_THROW(compare_written(folder, a, b), InputError);
  EXPECT_THROW(compare_report_files(folder.path() / "a.json", folder.path() / "missing.json"),
               InputError);
}

TEST(ReportCompareReports, AlphaOutsideTheUnitIntervalIsBadInput) {
  const ReportData empty;
  EXPECT_THROW(compare_reports(empty, empty, 0.0), InputError);
  EXPECT_THROW(compare_reports(empty, empty, 1.5), InputError);
  EXPECT_THROW(compare_reports(empty, empty, std::nan("")), InputError);
  EXPECT_NO_THROW(compare_reports(empty, empty, 1.0));
}

// ---------------------------------------------------------------------------------------------
// JSON

TEST(ReportCompareJson, FieldsAreThoseOfTheSchemasComparison) {
  const nlohmann::json schema =
      nlohmann::json::parse(read_text(fs::path(PCBENCH_SOURCE_DIR) / "results/report.schema.json"));
  const nlohmann::json& definition = schema.at("$defs").at("comparison");
  ReportData a, b;
  a.runs = {ReportRun{.id = kId1, .status = "ok", .estimates = {1, 1}},
            ReportRun{.id = kId2, .status = "ok", .estimates = {1, 2, 3}}};
  b.runs = {ReportRun{.id = kId1, .status = "ok", .estimates = {2, 2}},
            ReportRun{.id = kId2, .status = "ok", .estimates = {1, 2, 3.5}}};
  const ComparisonOutcome outcome = compare_reports(a, b, 0.05);
  const nlohmann::ordered_json written = comparisons_json(outcome.comparisons);
  ASSERT_EQ(written.size(), 2u);
  for (const auto& comparison : written) {
    for (const auto& required : definition.at("required")) {
      EXPECT_TRUE(comparison.contains(required.get<std::string>())) << required;
    }
    for (const auto& item : comparison.items()) {
      EXPECT_TRUE(definition.at("properties").contains(item.key()))
          << item.key() << " is not declared in $defs/comparison";
    }
  }
  // Constant replicates that differ: an infinite statistic is written as null, p = 0.
  EXPECT_TRUE(written[0]["statistic"].is_null());
  EXPECT_EQ(written[0]["p_value"], 0.0);
  EXPECT_EQ(written[0]["result"], "biased");
  EXPECT_EQ(written[0]["a"], kId1);
  EXPECT_EQ(written[0]["alpha"], 0.05);
  EXPECT_EQ(written[1]["test"], "welch");
  EXPECT_EQ(written[1]["expect"], "consistent");
  EXPECT_EQ(written[1]["statistic"], outcome.comparisons[1].statistic);

  const nlohmann::ordered_json whole = outcome_json(outcome);
  EXPECT_EQ(whole["comparisons"], written);
  for (const char* key : {"only_in_a", "only_in_b", "not_compared", "warnings"}) {
    EXPECT_TRUE(whole[key].is_array()) << key;
  }
}

}  // namespace
}  // namespace pcbench
