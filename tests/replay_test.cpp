// `pcbench replay`: every replayed sample is the one the run tallied (summed in order they give
// the run's replicate estimates bit for bit, fresh and shared pools, across a batch boundary),
// the first non-finite sample replays as non-finite, and the printed command rebuilds the run.
#include "harness/run/replay.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "base/errors.h"
#include "base/tally.h"
#include "harness/commands/cli.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

// 300 samples: two batches, the second cut at N, in one chunk (so the run's sum is in order).
void expect_replays_sum_to_the_run(const RunPlan& plan) {
  const RunResult run = execute_run(plan, {.seed = 3});
  ASSERT_EQ(run.status, RunStatus::kOk);
  for (std::uint32_t r = 0; r < plan.replicates; ++r) {
    Tally tally;
    for (std::uint64_t s = 0; s < plan.samples; ++s) {
      const ReplayedSample replayed = replay_sample(plan, 3, r, s);
      ASSERT_EQ(replayed.estimate, replayed.estimate_alone) << "sample " << s;
      tally.add(replayed.estimate, s);
    }
    EXPECT_EQ(tally.mean(), run.replicates[r].estimate) << "replicate " << r;
  }
}

TEST(Replay, FreshPoolSamplesAreTheOnesTheRunTallied) {
  expect_replays_sum_to_the_run(plan_single("pcbpt", "door", {{"M", {"4"}}}, 300, 2));
}

TEST(Replay, SharedPoolSamplesAreTheOnesTheRunTallied) {
  expect_replays_sum_to_the_run(
      plan_single("lvc", "genz-gaussian", {{"M", {"8"}}, {"pool", {"shared"}}}, 300, 2));
}

TEST(Replay, ShowsThePoolPAndTheDraws) {
  const RunPlan plan = plan_single("pcbpt", "genz-gaussian", {{"M", {"6"}}, {"K", {"3"}}}, 500, 2);
  const ReplayedSample r = replay_sample(plan, 1, 1, 260);
  EXPECT_EQ(r.batch_first, 256u);
  EXPECT_EQ(r.batch_count, 244u);
  ASSERT_EQ(r.pool.size(), 6u);
  ASSERT_EQ(r.pmf.size(), 6u);
  ASSERT_EQ(r.draws.size(), 3u);
  EXPECT_FALSE(r.camera.coordinates.empty());
  // The estimate is Σ_k f / (p(x) p(y)) / (M K P) over the draws.
  double sum = 0.0;
  for (std::uint32_t j : r.draws) sum += r.pool[j].contribution / (6.0 * 3.0 * r.pmf[j]);
  EXPECT_NEAR(sum, r.estimate, 1e-12 * std::fabs(r.estimate));
}

// A reservoir's choices: P is w_j / Σw over the sample's M candidates and the draws the pool
// paths its K reservoirs kept, so ris's estimate (1/K) Σ_k f(Y_k) W_k / p(y), W = Σw / (M p̂(Y)),
// is pcbpt's form Σ_k f / (p(x) p(y)) / (M K P) over the draws.
TEST(Replay, ShowsAReservoirsChoices) {
  const RunPlan plan =
      plan_single("ris", "genz-gaussian", {{"M", {"6"}}, {"K", {"3"}}, {"target", {"f"}}}, 300, 2);
  const ReplayedSample r = replay_sample(plan, 1, 0, 7);
  ASSERT_EQ(r.pool.size(), 6u);
  ASSERT_EQ(r.pmf.size(), 6u);
  ASSERT_EQ(r.draws.size(), 3u);
  double total = 0.0, sum = 0.0;
  for (double p : r.pmf) total += p;
  EXPECT_NEAR(total, 1.0, 1e-12);
  for (std::uint32_t j : r.draws) sum += r.pool[j].contribution / (6.0 * 3.0 * r.pmf[j]);
  EXPECT_NEAR(sum, r.estimate, 1e-12 * std::fabs(r.estimate));
  EXPECT_GT(r.estimate, 0.0);
}

TEST(Replay, TheFirstNonfiniteSampleReplaysAsNonfinite) {
  // sqrt of a negative number where x0 < 0.001: NaN in about 1 sample in 1000.
  const RunPlan plan =
      plan_single("plain", "expr", {{"f", {"sqrt(x0 - 0.001)"}}, {"exact", {"0.5"}}}, 4000, 2);
  const RunResult run = execute_run(plan, {.seed = 2});
  ASSERT_TRUE(run.first_nonfinite.has_value());
  const NonfiniteLocation at = *run.first_nonfinite;
  const ReplayedSample r = replay_sample(plan, at.seed, at.replicate, at.sample);
  EXPECT_TRUE(std::isnan(r.estimate));
  ASSERT_EQ(r.pool.size(), 1u);
  EXPECT_LT(r.pool[0].path.coordinates.at(0), 0.001);
  // Every sample before it was finite.
  for (std::uint64_t s = 0; s < at.sample; ++s) {
    EXPECT_TRUE(std::isfinite(replay_sample(plan, at.seed, at.replicate, s).estimate)) << s;
  }
}

TEST(Replay, TheCommandRebuildsTheRun) {
  const RunPlan plan = plan_single(
      "pcbpt", "expr",
      {{"f", {"x0 < 0.5 ? 0/0 : x0*y0"}}, {"M", {"4"}}, {"importance", {"uniform"}}}, 1000, 3);
  const std::optional<std::string> command =
      replay_command(plan, {.seed = 4, .replicate = 2, .sample = 7});
  ASSERT_TRUE(command.has_value());
  EXPECT_NE(command->find("-p 'f=x0 < 0.5 ? 0/0 : x0*y0'"), std::string::npos) << *command;
  EXPECT_NE(command->find("-n 1000 -r 3 --seed 4 --replicate 2 --sample 7 --run-id " + plan.id),
            std::string::npos)
      << *command;
  // The command's arguments (unquoted by hand here) replay in the CLI with the same run id.
  std::vector<std::string> args = {"replay", "-e", "pcbpt", "-i", "expr"};
  for (const ResolvedParams* params : {&plan.estimator_params, &plan.integrand_params}) {
    for (const auto& [key, value] : params->values()) {
      args.push_back("-p");
      args.push_back(key + "=" + to_text(value));
    }
  }
  for (const char* a :
       {"-n", "1000", "-r", "3", "--seed", "4", "--replicate", "2", "--sample", "7", "--run-id"}) {
    args.emplace_back(a);
  }
  args.push_back(plan.id);
  std::ostringstream out, err;
  const int status = run_cli(args, out, err);
  EXPECT_TRUE(status == 0 || status == 3) << err.str();
  EXPECT_NE(out.str().find("replay of run " + plan.id), std::string::npos) << out.str();
  // Another budget is another run: refused.
  args[args.size() - 11] = "999";
  std::ostringstream out2, err2;
  EXPECT_EQ(run_cli(args, out2, err2), 2);
  EXPECT_NE(err2.str().find("--run-id"), std::string::npos) << err2.str();
}

TEST(Replay, OutsideTheRunOrOnAScene) {
  const RunPlan plan = plan_single("plain", "genz-gaussian", {}, 100, 2);
  EXPECT_THROW(replay_sample(plan, 1, 2, 0), InputError);
  EXPECT_THROW(replay_sample(plan, 1, 0, 100), InputError);
  const RunPlan scene = plan_single("plain", "furnace", {{"resolution", {"8"}}}, 2, 2);
  EXPECT_FALSE(replay_command(scene, {}).has_value());
  EXPECT_THROW(replay_sample(scene, 1, 0, 0), InputError);
}

}  // namespace
}  // namespace pcbench
