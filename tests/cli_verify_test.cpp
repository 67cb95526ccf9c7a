// The verifier's commands end to end: verify (declared workloads, escalation, --exact,
// --estimates), compare, and a suite's pairwise comparisons.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "harness/commands/cli.h"
#include "harness/plan/plan.h"
#include "harness/verify/statistics.h"
#include "test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

class CliVerify : public ::testing::Test {
 protected:
  nlohmann::json report(const std::string& name) {
    return nlohmann::json::parse(read_text(folder_.path() / name / "report.json"));
  }
  std::string at(const std::string& name) { return (folder_.path() / name).string(); }

 private:
  TemporaryFolder folder_;
};

// A negative control alone runs on its declared integrand and budget and is flagged: exit 0.
TEST_F(CliVerify, NegativeControlUsesItsDeclaredWorkload) {
  const CliResult r = cli(
      {"verify", "-e", "ctl-wrong-count", "-n", "20000", "-r", "8", "-q", "--out", at("control")});
  EXPECT_EQ(r.status, 0) << r.err;
  const auto run = report("control")["runs"][0];
  EXPECT_EQ(run["integrand"], "form-factor");
  EXPECT_EQ(run["verdict"]["result"], "biased");
  EXPECT_EQ(run["verdict"]["expect"], "biased");
  const CliResult bad = cli({"verify", "-e", "plain", "--out", at("bad")});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("only a negative control declares its own integrand"), std::string::npos);
  EXPECT_FALSE(fs::exists(at("bad") + "/report.json"));
}

// Too few effective samples: verify runs again with 4 and 16 times the samples, at the share of
// alpha left for later stages, and records the earlier stages.
TEST_F(CliVerify, LowCountRunsEscalate) {
  const CliResult r = cli({"verify", "-e", "plain", "-i", "narrow-peak", "-n", "5000", "-r", "16",
                           "-q", "--out", at("escalated")});
  EXPECT_EQ(r.status, 0) << r.out;
  const auto run = report("escalated")["runs"][0];
  ASSERT_EQ(run["escalation"].size(), 2u);
  EXPECT_EQ(run["escalation"][0]["samples"], 5000);
  EXPECT_EQ(run["escalation"][0]["result"], "inconclusive");
  EXPECT_EQ(run["samples"], 80000);
  EXPECT_EQ(run["verdict"]["result"], "consistent");
  EXPECT_DOUBLE_EQ(run["verdict"]["alpha"].get<double>(), 0.01 / 2 / 2);
  // Its power statement uses the share of alpha the last stage was decided at.
  EXPECT_NEAR(run["verdict"]["min_detectable_bias"].get<double>(),
              detectable_multiplier(0.01 / 2 / 2, run["verdict"]["dof"].get<double>()) *
                  run["aggregates"]["stderr"].get<double>(),
              1e-12 * run["verdict"]["min_detectable_bias"].get<double>());
  // `run` does not escalate.
  EXPECT_EQ(cli({"run", "-e", "plain", "-i", "narrow-peak", "-n", "5000", "-r", "16", "-q", "--out",
                 at("once")})
                .status,
            1);
  EXPECT_TRUE(report("once")["runs"][0]["escalation"].empty());
}

TEST_F(CliVerify, AlphaOutsideTheOpenIntervalIsBadInput) {
  for (const char* alpha : {"0", "1", "-0.1", "x"}) {
    EXPECT_EQ(cli({"verify", "-e", "plain", "-i", "form-factor", "--alpha", alpha}).status, 2)
        << alpha;
  }
}

// Replicate estimates from a file, against a reference and against a second file.
TEST_F(CliVerify, EstimatesFromAFile) {
  std::ofstream(at("a.txt")) << "1.01\n0.99\n1.02\n0.98\n1.00\n1.01\n0.99\n1.00\n";
  std::ofstream(at("b.txt")) << "1.21\n1.19\n1.22\n1.18\n1.20\n1.21\n1.19\n1.20\n";
  EXPECT_EQ(
      cli({"verify", "--estimates", at("a.txt"), "--reference", "1", "--out", at("r1")}).status, 0);
  EXPECT_EQ(report("r1")["external"][0]["verdict"]["result"], "consistent");
  EXPECT_EQ(cli({"verify", "--estimates", at("a.txt"), "--against", at("b.txt"), "--out", at("r2")})
                .status,
            1);
  EXPECT_EQ(report("r2")["external"][0]["verdict"]["result"], "biased");
  EXPECT_EQ(cli({"verify", "--estimates", at("a.txt"), "--out", at("r3")}).status, 2);
  EXPECT_EQ(cli({"verify", "--estimates", at("a.txt"), "-e", "plain", "--reference", "1"}).status,
            2);
}

// compare pairs runs by id; a suite with "compare": "pairwise" tests every pair on an integrand,
// and a control paired with an honest estimator is expected to differ.
TEST_F(CliVerify, CompareAndPairwise) {
  ASSERT_EQ(cli({"run", "-e", "plain", "-i", "form-factor", "-n", "2000", "-r", "8", "-q", "--out",
                 at("a")})
                .status,
            0);
  ASSERT_EQ(cli({"run", "-e", "plain", "-i", "form-factor", "-n", "2000", "-r", "8", "-s", "2",
                 "-q", "--out", at("b")})
                .status,
            0);
  const CliResult c =
      cli({"compare", at("a") + "/report.json", at("b") + "/report.json", "--out", at("c")});
  EXPECT_EQ(c.status, 0) << c.err;
  ASSERT_EQ(report("c")["comparisons"].size(), 1u);
  EXPECT_EQ(report("c")["comparisons"][0]["result"], "consistent");

  std::ofstream(at("pairwise.json")) << R"({"name": "pairwise", "compare": "pairwise",
    "defaults": {"samples": 20000, "replicates": 8},
    "runs": [{"estimator": "plain", "integrand": "form-factor"},
             {"estimator": "vc-all", "integrand": "form-factor"},
             {"estimator": "ctl-wrong-count", "integrand": "form-factor"}]})";
  const CliResult p = cli({"run", at("pairwise.json"), "-q", "--out", at("p")});
  EXPECT_EQ(p.status, 0) << p.out;
  const auto comparisons = report("p")["comparisons"];
  ASSERT_EQ(comparisons.size(), 3u);
  int differ = 0;
  for (const auto& comparison : comparisons) {
    EXPECT_EQ(comparison["result"], comparison["expect"]);
    differ += comparison["expect"] == "biased";
  }
  EXPECT_EQ(differ, 2);
}

// Without a reference, verify tests estimators against each other (two-sample Welch): honest
// pairs agree, and a negative control differs from each of them.
TEST_F(CliVerify, WithoutAReferenceEstimatorsAreComparedPairwise) {
  const CliResult r = cli({"verify", "-e", "plain,pcbpt,ctl-wrong-count", "-i", "expr", "-p",
                           "f=x0*y0+sin(x0)", "-n", "20000", "-r", "8", "-q", "--out", at("nr")});
  EXPECT_EQ(r.status, 0) << r.out;
  const auto report = this->report("nr");
  ASSERT_EQ(report["comparisons"].size(), 3u);
  for (const auto& c : report["comparisons"]) EXPECT_EQ(c["result"], c["expect"]);
  for (const auto& run : report["runs"]) EXPECT_EQ(run["verdict"]["result"], "inconclusive");
}

// A constant integrand: every replicate gives the same bits, so the standard error is 0, and the
// mean may sit an ulp off the exact value (vc-all sums its 16 terms plainly). That is tested
// against the rounding bound (harness/verify/rounding_bound.h): consistent, and a wrong exact value
// is still biased.
TEST_F(CliVerify, ConstantIntegrandIsTestedAgainstTheRoundingBound) {
  struct Case {
    std::string f, exact, name;
    int status;
    std::string result;
  };
  const std::vector<Case> cases = {{"f=0.1+0*x0*y0", "exact=0.1", "tenth", 0, "consistent"},
                                   {"f=1/3", "exact=0.3333333333333333", "third", 0, "consistent"},
                                   {"f=0.1+0*x0*y0", "exact=0.1000001", "wrong", 1, "biased"}};
  for (const Case& c : cases) {
    const CliResult r = cli({"verify", "-e", "vc-all", "-i", "expr", "-p", c.f, "-p", c.exact, "-p",
                             "M=16", "-n", "20000", "-r", "8", "-q", "--out", at(c.name)});
    EXPECT_EQ(r.status, c.status) << c.f << " " << c.exact << "\n" << r.out << r.err;
    const auto run = report(c.name)["runs"][0];
    // The situation the rule is for: no spread, and a mean other than the exact value's double.
    EXPECT_EQ(run["aggregates"]["stderr"], 0.0) << c.name;
    EXPECT_NE(run["aggregates"]["mean"], run["reference"]["value"]) << c.name;
    EXPECT_EQ(run["verdict"]["result"], c.result) << c.name;
    EXPECT_GT(run["verdict"]["rounding_bound"].get<double>(), 0.0) << c.name;
    EXPECT_NE(run["verdict"]["reason"].get<std::string>().find(
                  "standard error 0 below the rounding bound"),
              std::string::npos)
        << run["verdict"]["reason"];
  }
  // Without an exact value the estimators are compared pairwise, each mean with its own bound:
  // plain gives 0.1, vc-all 0.1 + 1 ulp.
  const CliResult r = cli({"verify", "-e", "plain,vc-all", "-i", "expr", "-p", "f=0.1+0*x0*y0",
                           "-p", "M=16", "-n", "20000", "-r", "8", "-q", "--out", at("pair")});
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  const auto pair = report("pair");
  ASSERT_EQ(pair["comparisons"].size(), 1u);
  const auto& c = pair["comparisons"][0];
  EXPECT_NE(c["mean_a"], c["mean_b"]);
  EXPECT_EQ(c["result"], "consistent") << c["reason"];
  EXPECT_NE(c["reason"].get<std::string>().find("tested against the rounding bound"),
            std::string::npos)
      << c["reason"];
}

// Equal time: a pilot picks N from the CPU seconds per replicate, the report records it, the
// id is that of the requested budget, and `--samples N` replays the same numbers. N depends on
// the machine's speed, so the random numbers do too: the verdict is not asserted here (at
// alpha = 0.01 it would fail one run in a hundred), only that the run finished and replays.
TEST_F(CliVerify, EqualTimeBudgetReplaysWithTheChosenSampleCount) {
  const int timed_status = cli({"run", "-e", "pcbpt", "-i", "blocker", "--seconds", "0.05", "-r",
                                "4", "-q", "--out", at("timed")})
                               .status;
  ASSERT_TRUE(timed_status == 0 || timed_status == 1) << timed_status;
  const auto timed = report("timed")["runs"][0];
  EXPECT_EQ(timed["status"], "ok");
  EXPECT_EQ(timed["budget"]["seconds"], 0.05);
  EXPECT_GT(timed["budget"]["pilot_cpu_seconds_per_sample"].get<double>(), 0.0);
  const std::uint64_t n = timed["samples"].get<std::uint64_t>();
  EXPECT_GE(n, 1024u);
  EXPECT_EQ(n % 256, 0u);
  // The replay gives the same numbers, hence the same verdict and exit status.
  ASSERT_EQ(cli({"run", "-e", "pcbpt", "-i", "blocker", "--samples", std::to_string(n), "-r", "4",
                 "-q", "--out", at("replay")})
                .status,
            timed_status);
  const auto replay = report("replay")["runs"][0];
  EXPECT_NE(replay["id"], timed["id"]);
  for (std::size_t r = 0; r < 4; ++r) {
    EXPECT_EQ(replay["replicates"][r]["estimate"], timed["replicates"][r]["estimate"]) << r;
  }
  EXPECT_EQ(
      cli({"run", "-e", "plain", "-i", "blocker", "--seconds", "1", "--samples", "10"}).status, 2);
  std::ofstream(at("both.json"))
      << R"({"runs": [{"estimator": "plain", "integrand": "blocker", "samples": 5, "seconds": 1}]})";
  EXPECT_EQ(cli({"run", at("both.json")}).status, 2);
}

// Equal time on a scene: the pilot renders the whole image at 2 samples per pixel, the run takes
// N ≥ 1 samples per pixel from it, and `--samples N` replays the same images bit for bit. N
// depends on the machine's speed: only its bounds are asserted.
TEST_F(CliVerify, EqualTimeSceneBudgetReplaysWithTheChosenSamplesPerPixel) {
  const std::vector<std::string> scene = {"run",           "-e", "pt", "-i", "furnace", "-p",
                                          "resolution=16", "-r", "3"};
  std::vector<std::string> timed_args = scene;
  for (const char* a : {"--seconds", "0.02", "--out"}) timed_args.emplace_back(a);
  timed_args.push_back(at("timed"));
  const CliResult timed_run = cli(timed_args);
  ASSERT_TRUE(timed_run.status == 0 || timed_run.status == 1) << timed_run.err;
  EXPECT_NE(timed_run.err.find("µs per sample per pixel -> "), std::string::npos) << timed_run.err;
  EXPECT_NE(timed_run.err.find(" samples per pixel for 0.02 s"), std::string::npos)
      << timed_run.err;
  const auto timed = report("timed")["runs"][0];
  EXPECT_EQ(timed["status"], "ok");
  EXPECT_EQ(timed["budget"]["seconds"], 0.02);
  EXPECT_EQ(timed["budget"]["pilot_samples"], 2);
  EXPECT_GT(timed["budget"]["pilot_cpu_seconds_per_sample"].get<double>(), 0.0);
  const std::uint64_t n = timed["samples"].get<std::uint64_t>();
  EXPECT_GE(n, 1u);
  EXPECT_LE(n, kMaxSamples);

  std::vector<std::string> replay_args = scene;
  for (const char* a : {"-q", "--samples"}) replay_args.emplace_back(a);
  replay_args.push_back(std::to_string(n));
  replay_args.push_back("--out");
  replay_args.push_back(at("replay"));
  ASSERT_EQ(cli(replay_args).status, timed_run.status);
  const auto replay = report("replay")["runs"][0];
  EXPECT_NE(replay["id"], timed["id"]);
  EXPECT_EQ(replay["budget"]["pilot_samples"], 0);
  ASSERT_EQ(replay["replicates"].size(), 3u);
  for (std::size_t r = 0; r < 3; ++r) {
    EXPECT_EQ(replay["replicates"][r]["estimate"], timed["replicates"][r]["estimate"]) << r;
  }
  const auto image_of = [&](const std::string& name, const nlohmann::json& run) {
    return read_text(fs::path(at(name)) / run["image"]["files"]["mean"].get<std::string>());
  };
  EXPECT_EQ(image_of("replay", replay), image_of("timed", timed));
}

}  // namespace
}  // namespace pcbench
