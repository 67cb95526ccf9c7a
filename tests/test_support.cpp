#include "tests/test_support.h"

#include "harness/commands/cli.h"
#include "harness/run/runner.h"
#include "harness/verify/statistics.h"

#include <unistd.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <fstream>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace pcbench {

RunPlan plan_single(const std::string& estimator, const std::string& integrand,
                    std::map<std::string, std::vector<std::string>> params, std::uint64_t samples,
                    std::uint32_t replicates) {
  GridRequest grid{.estimators = {estimator},
                   .integrands = {integrand},
                   .params = std::move(params),
                   .samples = samples,
                   .replicates = replicates,
                   .where = "test"};
  return plan_runs({grid}, {}).at(0);
}

double chi_square_uniform_p_value(const std::vector<double>& counts) {
  const double total = std::accumulate(counts.begin(), counts.end(), 0.0);
  const double expected = total / static_cast<double>(counts.size());
  double statistic = 0.0;
  for (double c : counts) statistic += (c - expected) * (c - expected) / expected;
  const boost::math::chi_squared distribution(static_cast<double>(counts.size() - 1));
  return boost::math::cdf(boost::math::complement(distribution, statistic));
}

double chi_square_p_value(const std::vector<double>& observed,
                          const std::vector<double>& probabilities) {
  if (observed.size() != probabilities.size()) {
    throw std::invalid_argument("chi_square_p_value: sizes differ");
  }
  constexpr double kMinExpected = 5.0;
  const double total = std::accumulate(observed.begin(), observed.end(), 0.0);
  std::vector<double> group_observed, group_expected;
  double o = 0.0, e = 0.0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    o += observed[i];
    e += probabilities[i] * total;
    if (e >= kMinExpected) {
      group_observed.push_back(o);
      group_expected.push_back(e);
      o = e = 0.0;
    }
  }
  if (group_expected.empty()) throw std::invalid_argument("chi_square_p_value: too few samples");
  group_observed.back() += o;
  group_expected.back() += e;
  if (group_expected.size() < 2) return 1.0;  // one group: nothing to test
  double statistic = 0.0;
  for (std::size_t g = 0; g < group_expected.size(); ++g) {
    const double d = group_observed[g] - group_expected[g];
    statistic += d * d / group_expected[g];
  }
  const boost::math::chi_squared distribution(static_cast<double>(group_expected.size() - 1));
  return boost::math::cdf(boost::math::complement(distribution, statistic));
}

TemporaryFolder::TemporaryFolder() {
  std::string pattern = (std::filesystem::temp_directory_path() / "pcbench-test-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  path_ = pattern;
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::vector<std::string> files_under(const std::filesystem::path& folder) {
  std::vector<std::string> files;
  if (!std::filesystem::exists(folder)) return files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    if (entry.is_regular_file() || entry.is_symlink()) {
      files.push_back(std::filesystem::relative(entry.path(), folder).string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  out.flush();
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

nlohmann::json small_report(const std::vector<nlohmann::json>& runs, std::uint64_t seed) {
  return {{"schema_version", 1},
          {"suite", "test"},
          {"context", {{"seed", seed}, {"threads", 1}, {"git_commit", "unknown"}}},
          {"runs", runs},
          {"comparisons", nlohmann::json::array()}};
}

nlohmann::json small_report_run(const std::string& id, const std::vector<double>& estimates,
                                const std::string& status, const std::string& estimator,
                                const std::string& integrand) {
  nlohmann::json replicates = nlohmann::json::array();
  for (double e : estimates) replicates.push_back({{"estimate", e}, {"n", 1000}, {"nonfinite", 0}});
  return {{"id", id},
          {"estimator", estimator},
          {"integrand", integrand},
          {"params", nlohmann::json::object()},
          {"status", status},
          {"error", status == "ok" ? nlohmann::json(nullptr) : nlohmann::json("it failed")},
          {"samples", 1000},
          {"replicates", replicates}};
}

CliResult cli(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int status = run_cli(args, out, err);
  return {status, out.str(), err.str()};
}

nlohmann::json report_at(const std::filesystem::path& folder) {
  return nlohmann::json::parse(read_text(folder / "report.json"));
}

void InTemporaryFolder::SetUp() {
  previous_ = std::filesystem::current_path();
  std::filesystem::current_path(folder_.path());
}

void InTemporaryFolder::TearDown() {
  std::filesystem::current_path(previous_);
}

void expect_family_consistent(const std::vector<RunPlan>& plans, std::uint64_t seed, double alpha) {
  std::vector<Verdict> verdicts;
  verdicts.reserve(plans.size());
  for (const RunPlan& plan : plans) {
    const RunResult result = execute_run(plan, {.seed = seed});
    ASSERT_EQ(result.status, RunStatus::kOk) << plan.where << ": " << result.error;
    verdicts.push_back(test_against_reference(result, "consistent"));
  }
  std::vector<Verdict*> family;
  for (Verdict& v : verdicts) family.push_back(&v);
  decide_family(family, alpha);
  for (std::size_t i = 0; i < plans.size(); ++i) {
    EXPECT_EQ(verdicts[i].result, "consistent")
        << plans[i].estimator->name << " on " << plans[i].integrand->name << " (" << plans[i].where
        << "): " << verdicts[i].reason;
  }
}

std::string scene_test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name) c = c == '-' ? '_' : c;
  return name;
}

}  // namespace pcbench
