// The command line end to end, in process: exit statuses, nothing written on bad input, and
// report numbers independent of the thread count.
#include "harness/commands/cli.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "tests/test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

class CliInFolder : public InTemporaryFolder {};

TEST(Cli, HelpAndVersionExitZero) {
  EXPECT_EQ(cli({"--help"}).status, 0);
  EXPECT_EQ(cli({"run", "--help"}).status, 0);
  const CliResult version = cli({"--version"});
  EXPECT_EQ(version.status, 0);
  EXPECT_NE(version.out.find("pcbench"), std::string::npos);
}

TEST(Cli, ListNamesEveryKind) {
  const CliResult text = cli({"list"});
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("plain"), std::string::npos);
  EXPECT_NE(text.out.find("genz-gaussian"), std::string::npos);
  const CliResult json = cli({"list", "--json"});
  ASSERT_EQ(json.status, 0);
  const auto parsed = nlohmann::json::parse(json.out);
  ASSERT_TRUE(parsed["estimators"].is_array());
  EXPECT_EQ(parsed["estimators"][0]["name"], "plain");
  EXPECT_EQ(parsed["estimators"][0]["biased"], false);
  EXPECT_TRUE(parsed["integrands"][0]["exact"].is_boolean());
  EXPECT_TRUE(parsed["scenes"].is_array());
}

struct BadInput {
  std::vector<std::string> args;
  std::string message;  // a fragment the error must contain
};

// Every kind of bad input: exit 2, a message with the location or the valid choices, and
// nothing written to the working folder.
TEST_F(CliInFolder, BadInputExitsTwoAndWritesNothing) {
  {
    std::ofstream suite("broken.json");
    suite << "{\"runs\": [{\"estimator\": \"plain\",\n \"integrand\": }]}";
  }
  {
    std::ofstream suite("unknown_key.json");
    suite << R"({"runs": [{"estimator": "plain", "integrand": "genz-gaussian", "sample": 5}]})";
  }
  std::ofstream("duplicate.json")
      << R"({"runs": [{"estimator": "plain", "integrand": "genz-gaussian",
                       "params": {"sharpness": 4, "sharpness": 5}}]})";
  std::ofstream("contradiction.json")
      << R"({"runs": [{"estimator": "plain", "integrand": "genz-gaussian", "expect": "consistent"},
                      {"estimator": "plain", "integrand": "genz-gaussian", "expect": "biased"}]})";
  std::ofstream("no_emitter.scene.json")
      << R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
             "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
             "shapes": [{"type": "quad", "material": "white",
                         "corners": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]}]})";
  std::ofstream("scene_seconds.json")
      << R"({"runs": [{"estimator": "pt", "integrand": "furnace", "seconds": 0}]})";
  // Below a millisecond a replicate would time the clock: the suite key has the CLI's range.
  std::ofstream("tiny_seconds.json")
      << R"({"runs": [{"estimator": "plain", "integrand": "genz-gaussian", "seconds": 1e-4}]})";

  std::ofstream("paired_text.json")
      << R"({"paired": "yes", "runs": [{"estimator": "pt", "integrand": "furnace"}]})";
  std::ofstream("truncated.json") << R"({"runs": [{"estimator": "plain", "integ)";
  // JSON has no NaN: a coordinate beyond the double range is the nearest a file gets to one.
  const char* scene_head = R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
    "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [{"type": "triangle", "material": "white", "emission": [1, 1, 1], "corners": )";
  std::ofstream("overflow.scene.json") << scene_head << "[[0, 0, 0], [1, 0, 0], [1, 1e999, 0]]}]}";
  std::ofstream("flat.scene.json") << scene_head << "[[0, 0, 0], [1, 0, 0], [2, 0, 0]]}]}";
  const std::vector<BadInput> cases = {
      {{"run", "duplicate.json"}, "key 'sharpness' appears twice"},
      {{"run", "truncated.json"}, "truncated.json:1:"},
      {{"run", "-e", "vc-all", "-i", "genz-gaussian", "-p", "M=0"}, "'M' = '0': out of range"},
      {{"run", "-e", "pcbpt", "-i", "door-ajar", "-p", "visibility=cache-point", "-p",
        "uniform_mix=0"},
       "uniform_mix = 0 needs lookup=tile and visibility=ignored"},
      {{"run", "-e", "lvc", "-i", "genz-gaussian", "-p", "K=0"}, "'K' = '0': out of range"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-n", "-5"}, "--samples"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-p", "light_dims=40"}, "[1, 32]"},
      {{"verify", "-e", "plain", "-i", "genz-gaussian", "--alpha", "0"}, "alpha must be in (0, 1)"},
      {{"verify", "-e", "plain", "-i", "genz-gaussian", "--alpha", "1"}, "alpha must be in (0, 1)"},
      {{"run", "-e", "plain", "-i", "expr", "-p", "f=x0*y0 + x1"}, "variables: x0, y0"},
      {{"run", "-e", "plian", "-i", "genz-gaussian"}, "did you mean 'plain'?"},
      {{"run", "-e", "plain", "-i", "overflow.scene.json"},
       "overflow.scene.json:3:119: [json.exception.out_of_range.406] number overflow"},
      {{"run", "-e", "plain", "-i", "flat.scene.json"}, "triangle 0 is degenerate"},
      // Scenes.
      {{"run", "-e", "ctl-cull-small", "-i", "cornell"}, "does not render scenes"},
      {{"run", "-e", "pt", "-i", "genz-gaussian"}, "works on scenes only"},
      {{"run", "-e", "plain", "-i", "cornell", "-p", "resolution=0"}, "resolution '0'"},
      {{"run", "-e", "plain", "-i", "cornell", "-p", "resolution=64y64"}, "resolution"},
      {{"run", "-e", "plain", "-i", "cornell", "-p", "max_length=0"}, "out of range"},
      {{"run", "-e", "pcbpt", "-i", "cornell", "-p", "K=0"}, "out of range"},
      {{"run", "-e", "pcbpt", "-i", "cornell", "-p", "uniform_mix=2"}, "out of range"},
      {{"run", "-e", "pcbpt", "-i", "cornell", "-p", "importance=f"}, "read by no estimator"},
      {{"run", "-e", "plain", "-i", "furnace", "--seconds", "0"},
       "--seconds: Value 0 not in range"},
      {{"run", "-e", "pt", "-i", "cornell", "--seconds", "2e6"},
       "--seconds: Value 2e6 not in range"},
      {{"run", "scene_seconds.json"},
       "/runs/0/seconds: must be a number of seconds in [0.001, 1e+06]"},
      {{"run", "tiny_seconds.json"},
       "/runs/0/seconds: must be a number of seconds in [0.001, 1e+06]"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "--seconds", "1e-4"}, "--seconds"},
      {{"run", "-e", "plain", "-i", "missing.scene.json"}, "missing.scene.json"},
      {{"run", "-e", "plain", "-i", "no_emitter.scene.json"}, "emitter"},
      {{"run", "-e", "plain", "-i", "cornel"}, "valid integrands"},
      {{"run", "contradiction.json"}, "/runs/1: the same run as"},
      {{"run", "paired_text.json"}, "/paired"},
      {{"calibrate", "-e", "plain", "--paired"}, "--paired pairs scene runs"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "--out", ""}, "--out is empty"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "--seed", "-1"}, "--seed"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-n", "4294967295", "-r", "16777215"},
       "exceeds"},
      {{"run", "-e", "nope", "-i", "genz-gaussian"}, "valid estimators: plain"},
      {{"run", "-e", "plain", "-i", "nope"}, "valid integrands: genz-gaussian"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-p", "M=4"}, "read by no estimator"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-p", "sharpness=abc"}, "not a finite"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-p", "light_dims=0"}, "out of range"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-p", "sharpness"}, "key=value"},
      {{"run", "-e", "plain", "-i", "expr", "-p", "f=x0*(y0"}, "position"},
      {{"run", "-e", "plain", "-i", "expr", "-p", "f=x0, y0"},
       "parameter 'f', position 2: ',' outside a function's arguments"},
      {{"verify", "-e", "plain", "-i", "expr", "-p", "f=x0=2", "-p", "exact=2"},
       "parameter 'f', position 2: '=' assigns to a variable"},
      {{"run", "-e", "plain", "-i", "expr"}, "'f' is required"},
      {{"run", "-e", "plain"}, "--integrand is required"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-n", "0"}, "samples"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-r", "1"}, "replicates"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "-t", "0"}, "threads"},
      {{"run", "-e", "plain", "-i", "genz-gaussian", "--bogus"}, "--bogus"},
      {{"run"}, "give a suite file"},
      {{"run", "missing.json"}, "missing.json: cannot open"},
      {{"run", "broken.json"}, "broken.json:2:"},
      {{"run", "unknown_key.json"}, "/runs/0/sample: unknown key 'sample'; valid keys:"},
      {{"run", "unknown_key.json", "-e", "plain"}, "not both"},
      {{"frobnicate"}, "frobnicate"},
      {{}, "valid subcommands: list, run"},
  };
  const std::vector<std::string> before = files_under(folder());
  for (const BadInput& c : cases) {
    const CliResult r = cli(c.args);
    std::string command;
    for (const std::string& a : c.args) command += a + " ";
    EXPECT_EQ(r.status, 2) << command;
    EXPECT_NE((r.err + r.out).find(c.message), std::string::npos)
        << command << "\nmessage: " << r.err << r.out;
    EXPECT_EQ(files_under(folder()), before) << command << " wrote something";
  }
}

TEST_F(CliInFolder, OutputThatIsAFileIsBadInput) {
  { std::ofstream file("taken"); }
  const CliResult r =
      cli({"run", "-e", "plain", "-i", "genz-gaussian", "-n", "100", "-r", "2", "--out", "taken"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("not a folder"), std::string::npos);
}

TEST_F(CliInFolder, DefaultOutputFolderAndLatestLink) {
  const CliResult r = cli({"run", "-e", "plain", "-i", "genz-gaussian", "-n", "1000", "-r", "4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(folder() / "results" / "latest"));
  EXPECT_TRUE(fs::exists(folder() / "results" / "latest" / "report.json"));
  EXPECT_NE(r.out.find("report: results/runs/"), std::string::npos);
  EXPECT_NE(r.out.find("mean ± stderr"), std::string::npos);  // the summary table
  // A second run gets its own folder, and latest follows it.
  const CliResult again =
      cli({"run", "-e", "plain", "-i", "genz-gaussian", "-n", "1000", "-r", "4", "--quiet"});
  ASSERT_EQ(again.status, 0);
  EXPECT_EQ(again.out.find("mean ± stderr"), std::string::npos);  // --quiet: no table
  EXPECT_EQ(files_under(folder() / "results" / "runs").size(), 2u);
}

// Past 20 runs the summary ends its table with the estimator × integrand matrix: each cell the
// run's verdict and its efficiency relative to the column's first run not expected biased, as
// the report has them; with fewer runs there is no matrix.
TEST_F(CliInFolder, ManyRunsGetTheVerdictMatrix) {
  const std::vector<std::string> estimators = {"plain", "pcbpt", "lvc", "vc-all",
                                               "ctl-wrong-count"};
  const std::vector<std::string> integrands = {"form-factor", "genz-gaussian", "genz-continuous",
                                               "genz-corner-peak", "genz-oscillatory"};
  const auto joined = [](const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ",") + n;
    return out;
  };
  const CliResult r = cli({"run", "-e", joined(estimators), "-i", joined(integrands), "-n", "500",
                           "-r", "4", "--out", "many"});
  ASSERT_NE(r.status, 2) << r.err;
  const nlohmann::json report = report_at("many");
  ASSERT_EQ(report["runs"].size(), 25u);
  const std::string header = "efficiency relative to the first honest run per column:\n";
  const std::size_t start = r.out.find(header);
  ASSERT_NE(start, std::string::npos) << r.out;
  std::istringstream lines(r.out.substr(start + header.size()));
  std::string head;
  std::getline(lines, head);
  std::map<std::string, std::size_t> column_at;  // integrand -> the cell's first character
  for (const std::string& integrand : integrands) {
    column_at[integrand] = head.find(" " + integrand) + 1;
    ASSERT_NE(head.find(integrand), std::string::npos) << head;
  }
  std::map<std::string, std::string> row_of;  // estimator -> its line
  for (std::string line; std::getline(lines, line) && !line.empty() && line[0] != ' ';) {
    row_of[line.substr(0, line.find(' '))] = line;
  }
  ASSERT_EQ(row_of.size(), estimators.size()) << r.out;
  std::map<std::string, double> baseline;
  for (const auto& run : report["runs"]) {
    const std::string integrand = run["integrand"];
    if (!baseline.contains(integrand) && run["verdict"]["expect"] != "biased") {
      baseline[integrand] = run["aggregates"]["efficiency"].get<double>();
    }
  }
  for (const auto& run : report["runs"]) {
    const std::string& line = row_of[run["estimator"].get<std::string>()];
    const std::string integrand = run["integrand"];
    std::istringstream cell(line.substr(column_at[integrand]));
    std::string verdict, relative;
    cell >> verdict >> relative;
    const std::string result = run["verdict"]["result"];
    const std::string word = result == "consistent" ? "ok"
                             : result == "biased"   ? "BIASED"
                                                    : "inconcl.";
    EXPECT_EQ(verdict, word + (result == run["verdict"]["expect"] ? "" : "!")) << line;
    EXPECT_EQ(relative, fmt::format("{:.2g}x", run["aggregates"]["efficiency"].get<double>() /
                                                   baseline[integrand]))
        << line;
  }
  const CliResult few =
      cli({"run", "-e", "plain", "-i", "genz-gaussian", "-n", "500", "-r", "4", "--out", "few"});
  EXPECT_EQ(few.out.find("efficiency relative to the first honest run"), std::string::npos);
}

// The numbers of a report, without timings and context: what must not depend on threads.
nlohmann::json numbers_of(nlohmann::json report) {
  for (auto& run : report["runs"]) {
    run.erase("wall_seconds");
    for (auto& rep : run["replicates"]) {
      rep.erase("seconds");
      rep.erase("cpu_seconds");
    }
    run["aggregates"].erase("seconds_per_sample");
    run["aggregates"].erase("efficiency");
    run["aggregates"].erase("efficiency_low");
    run["aggregates"].erase("efficiency_high");
    for (auto& point : run["series"]) {
      point.erase("seconds");
      point.erase("cpu_seconds");
    }
  }
  return report["runs"];
}

TEST_F(CliInFolder, ReportNumbersAreIdenticalForOneAndTwoThreads) {
  const std::vector<std::string> common = {"run",
                                           "-e",
                                           "plain",
                                           "-i",
                                           "genz-gaussian,genz-oscillatory",
                                           "-p",
                                           "light_dims=1,2",
                                           "-n",
                                           "30001",
                                           "-r",
                                           "5",
                                           "--quiet"};
  auto one = common, two = common;
  one.insert(one.end(), {"--threads", "1", "--out", "one"});
  two.insert(two.end(), {"--threads", "2", "--out", "two"});
  ASSERT_EQ(cli(one).status, 0);
  ASSERT_EQ(cli(two).status, 0);
  const auto a = report_at("one"), b = report_at("two");
  EXPECT_EQ(a["context"]["threads"], 1);
  EXPECT_EQ(b["context"]["threads"], 2);
  EXPECT_EQ(a["runs"].size(), 4u);  // the grid: 2 integrands × 2 values of light_dims
  EXPECT_EQ(numbers_of(a), numbers_of(b));
}

// --interleave changes the order replicates run in, never their numbers; it adds efficiency
// ratios for analytic runs against the first run on each integrand (none for scenes).
TEST_F(CliInFolder, InterleavedRunsGiveTheSameNumbersAndEfficiencyRatios) {
  std::ofstream("suite.json") << R"({"name": "interleave", "defaults": {"replicates": 6},
    "grid": [{"estimator": ["plain", "vc-all"], "integrand": ["genz-gaussian"],
              "params": {"M": [4]}, "samples": 2048},
             {"estimator": ["plain", "vc-all"], "integrand": ["furnace"],
              "params": {"resolution": [8]}, "samples": 2}]})";
  const std::vector<std::string> common = {"run", "suite.json", "--quiet"};
  auto in_turn = common, one_by_one = common;
  in_turn.insert(in_turn.end(), {"--interleave", "--out", "interleaved"});
  one_by_one.insert(one_by_one.end(), {"--out", "sequential"});
  ASSERT_EQ(cli(in_turn).status, 0);
  ASSERT_EQ(cli(one_by_one).status, 0);
  auto a = report_at("interleaved"), b = report_at("sequential");
  for (auto* report : {&a, &b}) {
    for (auto& run : (*report)["runs"]) {
      if (!run.contains("image")) continue;
      for (const char* timed : {"rays_per_cpu_second", "cpu_seconds_per_replicate",
                                "rel_mse_at_1_cpu_second", "efficiency"}) {
        run["image"].erase(timed);
      }
    }
  }
  EXPECT_EQ(numbers_of(a), numbers_of(b));
  ASSERT_EQ(a["efficiency_ratios"].size(), 1u);  // vc-all against plain on genz-gaussian
  const auto& ratio = a["efficiency_ratios"][0];
  EXPECT_EQ(ratio["integrand"], "genz-gaussian");
  EXPECT_EQ(ratio["estimator"], "vc-all vs plain");
  EXPECT_TRUE(ratio["interleaved"].get<bool>());
  EXPECT_EQ(ratio["pairs"], 6);
  EXPECT_LT(ratio["low"].get<double>(), ratio["ratio"].get<double>());
  EXPECT_GT(ratio["high"].get<double>(), ratio["ratio"].get<double>());
  EXPECT_FALSE(b["efficiency_ratios"][0]["interleaved"].get<bool>());
}

TEST_F(CliInFolder, ExitStatusOneWhenAVerdictDiffersFromItsExpectation) {
  std::ofstream("suite.json") << R"({"name": "expect-biased",
    "runs": [{"estimator": "plain", "integrand": "genz-gaussian", "samples": 2000,
              "replicates": 8, "expect": "biased"}]})";
  const CliResult r = cli({"run", "suite.json", "--out", "out"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.out.find("(expected biased)"), std::string::npos);
  EXPECT_EQ(report_at("out")["suite"], "expect-biased");
}

TEST_F(CliInFolder, ExitStatusThreeWhenARunHasNonfiniteSamples) {
  const CliResult r =
      cli({"run", "-e", "plain", "-i", "expr,genz-gaussian", "-p", "f=x0 < 0.01 ? 1/0 : x0", "-p",
           "exact=0.5", "-n", "2000", "-r", "3", "--out", "out"});
  EXPECT_EQ(r.status, 3);
  const auto report = report_at("out");
  ASSERT_EQ(report["runs"].size(), 2u);
  EXPECT_EQ(report["runs"][0]["status"], "invalid");
  EXPECT_FALSE(report["runs"][0]["nonfinite_fields"].empty());
  EXPECT_EQ(report["runs"][1]["status"], "ok");  // the suite went on
}

TEST_F(CliInFolder, CommandLineBudgetOverridesTheSuite) {
  std::ofstream("suite.json") << R"({"defaults": {"samples": 500000, "seed": 7},
    "runs": [{"estimator": "plain", "integrand": "genz-gaussian", "samples": 900000}]})";
  ASSERT_EQ(cli({"run", "suite.json", "-n", "1000", "-r", "3", "--out", "out", "-q"}).status, 0);
  const auto report = report_at("out");
  EXPECT_EQ(report["runs"][0]["samples"], 1000);
  EXPECT_EQ(report["runs"][0]["replicates"].size(), 3u);
  EXPECT_EQ(report["context"]["seed"], 7);  // from the suite: --seed was not given
}

TEST_F(CliInFolder, CommandLineParamOverridesEveryRowOfTheSuite) {
  std::ofstream("suite.json") << R"({"defaults": {"samples": 1000, "replicates": 2},
    "grid": [{"estimator": ["plain"], "integrand": ["genz-gaussian"], "params": {"light_dims": ["2"]}},
             {"estimator": ["plain"], "integrand": ["genz-oscillatory"]}]})";
  ASSERT_EQ(cli({"run", "suite.json", "-p", "light_dims=3,4", "--out", "out", "-q"}).status, 0);
  const auto report = report_at("out");
  ASSERT_EQ(report["runs"].size(), 4u);  // each row's light_dims replaced by the grid 3, 4
  std::multiset<int> dims;
  for (const auto& run : report["runs"])
    dims.insert(run["integrand_params"]["light_dims"].get<int>());
  EXPECT_EQ(dims, (std::multiset<int>{3, 3, 4, 4}));
  // A parameter no row's estimator or integrand has is still bad input.
  EXPECT_EQ(cli({"run", "suite.json", "-p", "nonsense=1", "--out", "bad", "-q"}).status, 2);
}

}  // namespace
}  // namespace pcbench
