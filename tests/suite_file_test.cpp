#include "harness/plan/suite_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "base/errors.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

using Strings = std::vector<std::string>;

// The InputError message of parse_suite(text, "suite.json"), or "" when it does not throw.
std::string suite_error(const std::string& text) {
  try {
    parse_suite(text, "suite.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A row that parses; used to put a bad row after a good one.
constexpr const char* kGoodRow = R"({"estimator": "plain", "integrand": "genz-gaussian"})";

std::string suite_with_runs(const std::string& rows) {
  return std::string(R"({"name": "t", "runs": [)") + rows + "]}";
}

std::string suite_with_grid(const std::string& rows) {
  return std::string(R"({"name": "t", "grid": [)") + rows + "]}";
}

constexpr const char* kRowKeys =
    "valid keys: estimator, integrand, params, samples, seconds, replicates, "
    "expect";

TEST(SuiteFileParse, ValidSuiteWithDefaultsRunsAndGrid) {
  const SuiteRequest suite = parse_suite(R"({
    "name": "demo",
    "description": "a suite",
    "defaults": {"samples": 1000, "replicates": 8, "seed": 7},
    "runs": [
      {"estimator": "plain", "integrand": "genz-gaussian",
       "params": {"sharpness": 2, "center": "0.25"},
       "samples": 500, "replicates": 4, "expect": "consistent"},
      {"estimator": "plain", "integrand": "expr", "params": {"f": "x0*y0", "exact": 0.25}}
    ],
    "grid": [
      {"estimator": ["plain"], "integrand": ["genz-gaussian", "genz-oscillatory"],
       "params": {"sharpness": [1, 2.5, "3"], "light_dims": 2}}
    ]
  })",
                                         "suites/demo.json");
  EXPECT_EQ(suite.name, "demo");
  ASSERT_TRUE(suite.samples.has_value());
  EXPECT_EQ(*suite.samples, 1000u);
  ASSERT_TRUE(suite.replicates.has_value());
  EXPECT_EQ(*suite.replicates, 8u);
  ASSERT_TRUE(suite.seed.has_value());
  EXPECT_EQ(*suite.seed, 7u);
  ASSERT_EQ(suite.grids.size(), 3u);  // the runs rows first, then the grid entries

  const GridRequest& first = suite.grids[0];
  EXPECT_EQ(first.estimators, Strings{"plain"});
  EXPECT_EQ(first.integrands, Strings{"genz-gaussian"});
  ASSERT_EQ(first.params.size(), 2u);
  EXPECT_EQ(first.params.at("sharpness"), Strings{"2"});
  EXPECT_EQ(first.params.at("center"), Strings{"0.25"});
  EXPECT_EQ(first.samples, std::optional<std::uint64_t>(500));
  EXPECT_EQ(first.replicates, std::optional<std::uint32_t>(4));
  EXPECT_EQ(first.expect, std::optional<std::string>("consistent"));
  EXPECT_TRUE(contains(first.where, "suites/demo.json")) << first.where;
  EXPECT_TRUE(contains(first.where, "/runs/0")) << first.where;

  const GridRequest& second = suite.grids[1];
  EXPECT_EQ(second.integrands, Strings{"expr"});
  EXPECT_EQ(second.params.at("f"), Strings{"x0*y0"});
  EXPECT_EQ(second.params.at("exact"), Strings{"0.25"});
  EXPECT_FALSE(second.samples.has_value());
  EXPECT_FALSE(second.replicates.has_value());
  EXPECT_FALSE(second.expect.has_value());
  EXPECT_TRUE(contains(second.where, "/runs/1")) << second.where;

  const GridRequest& grid = suite.grids[2];
  EXPECT_EQ(grid.estimators, Strings{"plain"});
  EXPECT_EQ(grid.integrands, (Strings{"genz-gaussian", "genz-oscillatory"}));
  EXPECT_EQ(grid.params.at("sharpness"), (Strings{"1", "2.5", "3"}));
  EXPECT_EQ(grid.params.at("light_dims"), Strings{"2"});  // a scalar in a grid is a 1-list
  EXPECT_TRUE(contains(grid.where, "/grid/0")) << grid.where;
}

TEST(SuiteFileParse, DefaultsAreOptional) {
  const SuiteRequest suite = parse_suite(suite_with_runs(kGoodRow), "s.json");
  EXPECT_EQ(suite.name, "t");
  EXPECT_FALSE(suite.samples.has_value());
  EXPECT_FALSE(suite.replicates.has_value());
  EXPECT_FALSE(suite.seed.has_value());
  ASSERT_EQ(suite.grids.size(), 1u);
}

TEST(SuiteFileParse, NameDefaultsToUnnamed) {
  const SuiteRequest suite = parse_suite(std::string(R"({"runs": [)") + kGoodRow + "]}", "s");
  EXPECT_EQ(suite.name, "unnamed");
}

TEST(SuiteFileParse, JsonSyntaxErrorAtTheEndOfATruncatedFile) {
  // The input ends after the newline that closes line 3.
  const std::string message = suite_error("{\n\"name\": \"x\",\n\"runs\": [\n");
  EXPECT_EQ(message.rfind("suite.json:4:1:", 0), 0u) << message;
}

TEST(SuiteFileParse, JsonSyntaxErrorGivesFileLineAndColumn) {
  // The stray '@' is on line 3, column 3.
  const std::string message = suite_error("{\n  \"name\": \"x\",\n  @\n}");
  EXPECT_EQ(message.rfind("suite.json:3:3:", 0), 0u) << message;
  EXPECT_TRUE(contains(message, "syntax error")) << message;
}

TEST(SuiteFileParse, JsonSyntaxErrorOnTheFirstLine) {
  // The '}' closing an object that still needs a value is at line 1, column 10.
  const std::string message = suite_error(R"({"name": })");
  EXPECT_EQ(message.rfind("suite.json:1:10:", 0), 0u) << message;
}

TEST(SuiteFileParse, UnknownTopLevelKeyNamesPointerAndValidKeys) {
  const std::string message =
      suite_error(R"({"name": "t", "runz": [], "runs": [)" + std::string(kGoodRow) + "]}");
  EXPECT_TRUE(contains(message, "suite.json")) << message;
  EXPECT_TRUE(contains(message, "/runz")) << message;
  EXPECT_TRUE(contains(message, "valid keys: name, description, defaults, runs, grid")) << message;
}

TEST(SuiteFileParse, StrategyImagesIsABooleanOffByDefault) {
  const std::string row = std::string(kGoodRow);
  EXPECT_FALSE(parse_suite(suite_with_runs(row), "suite.json").strategy_images);
  EXPECT_TRUE(parse_suite(R"({"strategy_images": true, "runs": [)" + row + "]}", "suite.json")
                  .strategy_images);
  for (const char* bad : {R"("yes")", "1", "null", "[true]"}) {
    const std::string message =
        suite_error(std::string(R"({"strategy_images": )") + bad + R"(, "runs": [)" + row + "]}");
    EXPECT_TRUE(contains(message, "suite.json: /strategy_images: must be true or false"))
        << bad << ": " << message;
  }
}

TEST(SuiteFileParse, RequireMdbSetsScaleRequirementsOnTopOfTheDefaults) {
  const std::string row = std::string(kGoodRow);
  const SuiteRequest suite = parse_suite(
      R"({"require_mdb": {"image": 0.02, "32": 0.05}, "runs": [)" + row + "]}", "suite.json");
  EXPECT_EQ(suite.scale_requirements.at(128, false, true), 0.02);
  EXPECT_EQ(suite.scale_requirements.at(32, false, false), 0.05);
  EXPECT_EQ(suite.scale_requirements.at(8, true, false), 0.05);  // the default stays
  // null drops a requirement.
  EXPECT_FALSE(
      parse_suite(R"({"require_mdb": {"tile": null}, "runs": [)" + row + "]}", "suite.json")
          .scale_requirements.at(8, true, false)
          .has_value());
  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"image": 1.5})", "suite.json: /require_mdb/image: the required detectable bias"},
      {R"({"whole": 0.01})", "suite.json: /require_mdb/whole: scale 'whole' is not one of"},
      {R"({"image": "1%"})", "suite.json: /require_mdb/image: must be a finite number"},
      {R"([0.01])", "suite.json: /require_mdb: must be an object"}};
  for (const auto& [value, expected] : bad) {
    const std::string message =
        suite_error(R"({"require_mdb": )" + value + R"(, "runs": [)" + row + "]}");
    EXPECT_TRUE(contains(message, expected)) << value << ": " << message;
  }
}

TEST(SuiteFileParse, UnknownDefaultsKeyNamesPointerAndValidKeys) {
  const std::string message =
      suite_error(R"({"defaults": {"sample": 10}, "runs": [)" + std::string(kGoodRow) + "]}");
  EXPECT_TRUE(contains(message, "/defaults/sample")) << message;
  EXPECT_TRUE(contains(message, "valid keys: samples, seconds, replicates, seed")) << message;
}

TEST(SuiteFileParse, UnknownRowKeyNamesPointerAndValidKeys) {
  const std::string message = suite_error(suite_with_runs(
      std::string(kGoodRow) +
      R"(, {"estimater": "plain", "estimator": "plain", "integrand": "genz-gaussian"})"));
  EXPECT_TRUE(contains(message, "suite.json")) << message;
  EXPECT_TRUE(contains(message, "/runs/1/estimater")) << message;
  EXPECT_TRUE(contains(message, kRowKeys)) << message;
}

TEST(SuiteFileParse, UnknownGridKeyNamesPointerAndValidKeys) {
  const std::string message = suite_error(
      suite_with_grid(R"({"estimator": ["plain"], "integrand": ["genz-gaussian"], "param": {}})"));
  EXPECT_TRUE(contains(message, "/grid/0/param")) << message;
  EXPECT_TRUE(contains(message, kRowKeys)) << message;
}

TEST(SuiteFileParse, SamplesGivenAsAStringIsRejected) {
  const std::string message = suite_error(
      suite_with_runs(R"({"estimator": "plain", "integrand": "genz-gaussian", "samples": "10"})"));
  EXPECT_TRUE(contains(message, "/runs/0/samples")) << message;
  EXPECT_TRUE(contains(message, "must be an integer")) << message;
}

TEST(SuiteFileParse, NonIntegralOrZeroSamplesAreRejected) {
  for (const char* value : {"1.5", "0", "-3", "true", "null"}) {
    const std::string message = suite_error(suite_with_runs(
        std::string(R"({"estimator": "plain", "integrand": "genz-gaussian", "samples": )") + value +
        "}"));
    EXPECT_TRUE(contains(message, "/runs/0/samples")) << value << ": " << message;
  }
}

TEST(SuiteFileParse, SamplesAboveTheCounterLimitAreRejected) {
  const std::string message = suite_error(suite_with_runs(
      R"({"estimator": "plain", "integrand": "genz-gaussian", "samples": 4294967296})"));
  EXPECT_TRUE(contains(message, "/runs/0/samples")) << message;
  EXPECT_TRUE(contains(message, "out of range")) << message;
}

TEST(SuiteFileParse, OneReplicateIsRejectedInRowsAndDefaults) {
  const std::string row_message = suite_error(
      suite_with_runs(R"({"estimator": "plain", "integrand": "genz-gaussian", "replicates": 1})"));
  EXPECT_TRUE(contains(row_message, "/runs/0/replicates")) << row_message;
  EXPECT_TRUE(contains(row_message, "out of range")) << row_message;
  const std::string defaults_message =
      suite_error(R"({"defaults": {"replicates": 1}, "runs": [)" + std::string(kGoodRow) + "]}");
  EXPECT_TRUE(contains(defaults_message, "/defaults/replicates")) << defaults_message;
}

TEST(SuiteFileParse, NegativeSeedIsRejected) {
  const std::string message =
      suite_error(R"({"defaults": {"seed": -1}, "runs": [)" + std::string(kGoodRow) + "]}");
  EXPECT_TRUE(contains(message, "/defaults/seed")) << message;
  EXPECT_TRUE(contains(message, "must be an integer")) << message;
}

TEST(SuiteFileParse, SeedZeroIsAccepted) {
  const SuiteRequest suite =
      parse_suite(R"({"defaults": {"seed": 0}, "runs": [)" + std::string(kGoodRow) + "]}", "s");
  EXPECT_EQ(suite.seed, std::optional<std::uint64_t>(0));
}

TEST(SuiteFileParse, ListsInRunsRowsAreRejected) {
  const std::string integrand_message = suite_error(suite_with_runs(
      R"({"estimator": "plain", "integrand": ["genz-gaussian", "genz-oscillatory"]})"));
  EXPECT_TRUE(contains(integrand_message, "/runs/0/integrand")) << integrand_message;
  EXPECT_TRUE(contains(integrand_message, "only allowed in \"grid\"")) << integrand_message;

  const std::string estimator_message =
      suite_error(suite_with_runs(R"({"estimator": ["plain"], "integrand": "genz-gaussian"})"));
  EXPECT_TRUE(contains(estimator_message, "/runs/0/estimator")) << estimator_message;

  const std::string param_message = suite_error(suite_with_runs(
      std::string(kGoodRow) +
      R"(, {"estimator": "plain", "integrand": "genz-gaussian", "params": {"sharpness": [1, 2]}})"));
  EXPECT_TRUE(contains(param_message, "/runs/1/params/sharpness")) << param_message;
}

TEST(SuiteFileParse, EmptyListsInGridAreRejected) {
  const std::string integrand_message =
      suite_error(suite_with_grid(R"({"estimator": ["plain"], "integrand": []})"));
  EXPECT_TRUE(contains(integrand_message, "/grid/0/integrand")) << integrand_message;
  EXPECT_TRUE(contains(integrand_message, "empty list")) << integrand_message;

  const std::string param_message = suite_error(suite_with_grid(
      R"({"estimator": ["plain"], "integrand": ["genz-gaussian"], "params": {"sharpness": []}})"));
  EXPECT_TRUE(contains(param_message, "/grid/0/params/sharpness")) << param_message;
  EXPECT_TRUE(contains(param_message, "empty list")) << param_message;
}

TEST(SuiteFileParse, MissingEstimatorOrIntegrandIsRejected) {
  const std::string estimator_message =
      suite_error(suite_with_runs(std::string(kGoodRow) + R"(, {"integrand": "genz-gaussian"})"));
  EXPECT_TRUE(contains(estimator_message, "/runs/1")) << estimator_message;
  EXPECT_TRUE(contains(estimator_message, "missing \"estimator\"")) << estimator_message;

  const std::string integrand_message = suite_error(suite_with_grid(R"({"estimator": ["plain"]})"));
  EXPECT_TRUE(contains(integrand_message, "/grid/0")) << integrand_message;
  EXPECT_TRUE(contains(integrand_message, "missing \"integrand\"")) << integrand_message;
}

TEST(SuiteFileParse, ParameterValuesMustBeScalars) {
  const std::string message = suite_error(suite_with_runs(
      R"({"estimator": "plain", "integrand": "genz-gaussian", "params": {"center": {"a": 1}}})"));
  EXPECT_TRUE(contains(message, "/runs/0/params/center")) << message;
  const std::string in_list = suite_error(suite_with_grid(
      R"({"estimator": "plain", "integrand": "genz-gaussian", "params": {"center": [0.5, null]}})"));
  EXPECT_TRUE(contains(in_list, "/grid/0/params/center/1")) << in_list;
}

TEST(SuiteFileParse, WrongShapesAreRejectedWithTheirPointer) {
  EXPECT_TRUE(contains(suite_error("[]"), "suite.json: /: must be an object"));
  EXPECT_TRUE(contains(suite_error(R"({"runs": {}})"), "/runs: must be an array"));
  EXPECT_TRUE(contains(suite_error(R"({"runs": [3]})"), "/runs/0: must be an object"));
  EXPECT_TRUE(contains(suite_error(R"({"name": 5, "runs": [)" + std::string(kGoodRow) + "]}"),
                       "/name: must be a string"));
  EXPECT_TRUE(contains(suite_error(R"({"defaults": [], "runs": [)" + std::string(kGoodRow) + "]}"),
                       "/defaults: must be an object"));
  EXPECT_TRUE(contains(suite_error(suite_with_runs(
                           R"({"estimator": "plain", "integrand": "genz-gaussian", "expect": 1})")),
                       "/runs/0/expect: must be a string"));
  EXPECT_TRUE(contains(
      suite_error(
          suite_with_runs(R"({"estimator": "plain", "integrand": "genz-gaussian", "params": []})")),
      "/runs/0/params: must be an object"));
}

TEST(SuiteFileParse, SuiteWithoutRunsIsRejected) {
  EXPECT_TRUE(contains(suite_error(R"({"name": "empty"})"), "no \"runs\""));
  EXPECT_TRUE(contains(suite_error(R"({"name": "empty", "runs": [], "grid": []})"), "no \"runs\""));
}

// Found by the suite fuzz target (fuzz/regressions/suite/): nlohmann-json reports a number too
// large for a double as out_of_range, not as a parse error, and it escaped as an abort.
TEST(SuiteFileParse, NumberTooLargeForADoubleIsBadInputAtItsPlace) {
  const std::string message =
      suite_error(suite_with_runs("{\"estimator\": \"plain\",\n \"samples\": 1e999}"));
  EXPECT_TRUE(contains(message, "suite.json:2:13: ")) << message;
  EXPECT_TRUE(contains(message, "number overflow parsing '1e999'")) << message;
}

TEST(SuiteFileLoad, MissingFileIsAnInputErrorNamingThePath) {
  const TemporaryFolder folder;
  const std::string path = (folder.path() / "no-such-suite.json").string();
  try {
    load_suite(path);
    FAIL() << "a missing suite file was accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), path)) << e.what();
  }
}

TEST(SuiteFileLoad, ReadsAFileAndNamesItInErrors) {
  const TemporaryFolder folder;
  const std::filesystem::path good = folder.path() / "good.json";
  std::ofstream(good) << suite_with_runs(kGoodRow);
  const SuiteRequest suite = load_suite(good.string());
  ASSERT_EQ(suite.grids.size(), 1u);
  EXPECT_TRUE(contains(suite.grids[0].where, good.string())) << suite.grids[0].where;

  const std::filesystem::path bad = folder.path() / "bad.json";
  std::ofstream(bad) << R"({"runs": [{"estimator": "plain"}]})";
  try {
    load_suite(bad.string());
    FAIL() << "a row without an integrand was accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), bad.string() + ": /runs/0")) << e.what();
  }
}

}  // namespace
}  // namespace pcbench
