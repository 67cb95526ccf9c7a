// Equal-time budgets: the sample count a measured cost buys (analytic and scene rules), and a
// resumed scene run keeping the count its pilot chose. The pilot's measurement itself depends on
// the machine's speed; the command-line tests run it (tests/cli_verify_test.cpp).
#include "harness/run/equal_time.h"

#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "harness/run/run_store.h"
#include "harness/session/session.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

RunPlan furnace_plan(std::optional<double> seconds) {
  GridRequest grid{.estimators = {"pt"},
                   .integrands = {"furnace"},
                   .params = {{"resolution", {"8"}}},
                   .samples = seconds ? std::nullopt : std::optional<std::uint64_t>(4),
                   .seconds = seconds,
                   .replicates = 2,
                   .where = "test"};
  return plan_runs({grid}, {}).at(0);
}

TEST(EqualTimeRule, ScenesMeasureWholeImagesAndChooseAnyCountFromOne) {
  const PilotRule& rule = pilot_rule(furnace_plan(0.5));
  EXPECT_EQ(rule.samples, 2u);
  EXPECT_EQ(rule.least, 1u);
  EXPECT_EQ(samples_for_seconds(rule, 1.0, 0.3), 3u);   // floor(3.33)
  EXPECT_EQ(samples_for_seconds(rule, 1.0, 0.25), 4u);  // exactly 4
  EXPECT_EQ(samples_for_seconds(rule, 1.0, 5.0), 1u);   // a budget below one image: one image
  EXPECT_EQ(samples_for_seconds(rule, 1e6, 1e-9), kMaxSamples);
  EXPECT_EQ(samples_for_seconds(rule, 1.0, 0.0), 1u);  // nothing measured
}

TEST(EqualTimeRule, AnalyticRunsChooseWholeBatchesFrom1024) {
  const PilotRule& rule = pilot_rule(plan_single("plain", "genz-gaussian", {}, 1000, 2));
  EXPECT_EQ(rule.samples, 8192u);
  EXPECT_EQ(samples_for_seconds(rule, 1.0, 1e-6), 999936u);  // 3906 batches of 256
  EXPECT_EQ(samples_for_seconds(rule, 1.0, 1.0), 1024u);
  EXPECT_EQ(samples_for_seconds(rule, 1.0, std::nan("")), 1024u);
}

// The journal holds the run as its pilot chose it (3 samples per pixel): --resume restores that
// count and the pilot's figures instead of running a new pilot, which would choose another.
TEST(EqualTimeResume, ASceneRunKeepsTheSampleCountItsPilotChose) {
  TemporaryFolder folder;
  const std::vector<RunPlan> plans = {furnace_plan(0.5)};
  RunPlan chosen = with_chosen_samples(plans[0], 3);
  chosen.pilot_samples = 2;
  chosen.pilot_cpu_per_sample = 0.125;
  std::ostringstream out, err;
  RunStore::start(folder.path(), 1, "test", plans, err)
      .save(chosen, execute_run(chosen, {.seed = 1}), err);
  ASSERT_TRUE(err.str().empty()) << err.str();

  SessionOptions options;
  options.out_dir = folder.path().string();
  options.quiet = true;
  options.resume = std::make_shared<RunStore>(RunStore::resume(folder.path(), 1, plans));
  const int status = run_session(plans, options, out, err);
  EXPECT_TRUE(status == kExitOk || status == kExitVerdictDiffers) << status << err.str();
  const auto run = nlohmann::json::parse(read_text(folder.path() / "report.json"))["runs"][0];
  EXPECT_EQ(run["id"], plans[0].id);
  EXPECT_EQ(run["samples"], 3);
  EXPECT_EQ(run["budget"]["seconds"], 0.5);
  EXPECT_EQ(run["budget"]["pilot_samples"], 2);
  EXPECT_EQ(run["budget"]["pilot_cpu_seconds_per_sample"], 0.125);
  // The same numbers as `--samples 3`.
  const RunResult replay = execute_run(with_samples(plans[0], 3), {.seed = 1});
  ASSERT_EQ(run["replicates"].size(), replay.replicates.size());
  for (std::size_t r = 0; r < replay.replicates.size(); ++r) {
    EXPECT_EQ(run["replicates"][r]["estimate"].get<double>(), replay.replicates[r].estimate) << r;
  }
}

}  // namespace
}  // namespace pcbench
