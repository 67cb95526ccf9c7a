// Helpers shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/plan/plan.h"

namespace pcbench {

// The plan of one estimator on one integrand (params: key -> values, one value each).
RunPlan plan_single(const std::string& estimator, const std::string& integrand,
                    std::map<std::string, std::vector<std::string>> params, std::uint64_t samples,
                    std::uint32_t replicates);

// Runs every plan with `seed` and expects each to come out consistent with its reference when
// the runs are decided as one Holm family at `alpha` (a test's error budget over many runs).
void expect_family_consistent(const std::vector<RunPlan>& plans, std::uint64_t seed, double alpha);

// p-value of Pearson's chi-square test that `counts` come from equal-probability bins.
double chi_square_uniform_p_value(const std::vector<double>& counts);

// p-value of Pearson's chi-square test that `observed` counts come from bins of the given
// `probabilities` (summing to 1). Bins expected to hold fewer than 5 are pooled with the bins that
// follow them (a short last group joins the one before), so that the chi-square approximation
// holds; the degrees of freedom are the pooled groups less one.
double chi_square_p_value(const std::vector<double>& observed,
                          const std::vector<double>& probabilities);

// Whether two doubles have the same bits (a NaN equals only the same NaN; -0 differs from 0):
// what "the same numbers to the bit" means in the lanes tests.
inline bool bit_identical(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// A built-in scene's name as a parameterised test's name (gtest allows no '-').
std::string scene_test_name(const ::testing::TestParamInfo<std::string>& info);

// A fresh, empty temporary folder, removed when the object goes out of scope.
class TemporaryFolder {
 public:
  TemporaryFolder();
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// What `pcbench ARGS` returned and printed, run in process (harness/commands/cli.h).
struct CliResult {
  int status;
  std::string out;
  std::string err;
};
CliResult cli(const std::vector<std::string>& args);

// The report.json in `folder`, parsed.
nlohmann::json report_at(const std::filesystem::path& folder);

// Runs each test in a fresh temporary working folder, so that default output paths land there.
class InTemporaryFolder : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  const std::filesystem::path& folder() const { return folder_.path(); }

 private:
  TemporaryFolder folder_;
  std::filesystem::path previous_;
};

// Every regular file under `folder`, relative paths, sorted.
std::vector<std::string> files_under(const std::filesystem::path& folder);

std::string read_text(const std::filesystem::path& file);

// Writes `text` to `file` as it is (binary), replacing it; throws if it cannot.
void write_text(const std::filesystem::path& file, const std::string& text);

// A small pcbench report (schema_version 1, context.seed = `seed`) holding `runs`.
nlohmann::json small_report(const std::vector<nlohmann::json>& runs, std::uint64_t seed = 1);

// One run of such a report: id, estimator, integrand, status, and replicates[].estimate =
// `estimates`.
nlohmann::json small_report_run(const std::string& id, const std::vector<double>& estimates,
                                const std::string& status = "ok",
                                const std::string& estimator = "plain",
                                const std::string& integrand = "genz-gaussian");

}  // namespace pcbench
