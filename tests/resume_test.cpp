// --resume's pieces: a saved run reads back bit for bit (analytic, invalid and scene runs), the
// journal restores what it saved and refuses a journal of another seed or suite, and the command
// line's bad input around --resume exits 2 without writing anything.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "base/errors.h"
#include "harness/commands/cli.h"
#include "harness/run/run_store.h"
#include "harness/run/runner.h"
#include "harness/run/saved_run.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

SavedRun saved(const RunPlan& plan, std::uint64_t seed) {
  return {.id = plan.id,
          .seed = seed,
          .samples = plan.samples,
          .replicates = plan.replicates,
          .result = execute_run(plan, {.seed = seed})};
}

bool same_bits(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0;
}

// The text form holds every field in a form that reads back exactly, so a second round trip
// giving the same text means every field survived; a few fields are checked directly too.
void expect_round_trip(const SavedRun& run) {
  const std::string text = saved_run_text(run);
  const SavedRun back = read_saved_run(text);
  EXPECT_EQ(saved_run_text(back), text);
  EXPECT_EQ(back.id, run.id);
  EXPECT_EQ(back.result.status, run.result.status);
  ASSERT_EQ(back.result.replicates.size(), run.result.replicates.size());
  for (std::size_t r = 0; r < run.result.replicates.size(); ++r) {
    const ReplicateResult& a = run.result.replicates[r];
    const ReplicateResult& b = back.result.replicates[r];
    EXPECT_TRUE(same_bits(a.estimate, b.estimate)) << r;
    EXPECT_TRUE(same_bits(a.variance, b.variance)) << r;
    EXPECT_EQ(a.largest, b.largest);
    EXPECT_EQ(a.first_nonfinite_sample, b.first_nonfinite_sample);
    ASSERT_EQ(a.checkpoints.size(), b.checkpoints.size());
    for (std::size_t k = 0; k < a.checkpoints.size(); ++k) {
      EXPECT_TRUE(same_bits(a.checkpoints[k].estimate, b.checkpoints[k].estimate));
    }
  }
  ASSERT_EQ(back.result.images.size(), run.result.images.size());
  for (std::size_t i = 0; i < run.result.images.size(); ++i) {
    EXPECT_EQ(back.result.images[i].values, run.result.images[i].values);
  }
  EXPECT_EQ(back.result.scene_counters, run.result.scene_counters);
}

TEST(SavedRun, AnAnalyticRunReadsBackBitForBit) {
  expect_round_trip(saved(plan_single("pcbpt", "genz-gaussian", {}, 3000, 3), 4));
}

TEST(SavedRun, AnInvalidRunKeepsItsNonfiniteNumbersAndLocation) {
  const SavedRun run = saved(
      plan_single("plain", "expr", {{"f", {"x0 < 0.01 ? 1/0 : x0"}}, {"exact", {"0.5"}}}, 1000, 3),
      9);
  ASSERT_EQ(run.result.status, RunStatus::kInvalid);
  expect_round_trip(run);
  const SavedRun back = read_saved_run(saved_run_text(run));
  ASSERT_TRUE(back.result.first_nonfinite.has_value());
  EXPECT_EQ(back.result.first_nonfinite->sample, run.result.first_nonfinite->sample);
  EXPECT_TRUE(std::isinf(back.result.replicates[0].estimate) ||
              std::isnan(back.result.replicates[0].estimate));
}

TEST(SavedRun, ASceneRunKeepsItsImages) {
  const SavedRun run = saved(plan_single("plain", "furnace", {{"resolution", {"8"}}}, 2, 2), 1);
  ASSERT_EQ(run.result.status, RunStatus::kOk);
  ASSERT_EQ(run.result.images.size(), 2u);
  expect_round_trip(run);
}

TEST(SavedRun, ASceneRunKeepsItsStrategyImages) {
  const RunPlan plan = plan_single("plain", "cornell", {{"resolution", {"8"}}}, 2, 2);
  SavedRun run = saved(plan, 1);
  EXPECT_FALSE(run.result.strategy_images.has_value());  // not asked for
  run.result = execute_run(plan, {.seed = 1, .strategy_images = true});
  ASSERT_TRUE(run.result.strategy_images.has_value());
  expect_round_trip(run);
  const SavedRun back = read_saved_run(saved_run_text(run));
  ASSERT_TRUE(back.result.strategy_images.has_value());
  const StrategyImages& a = *run.result.strategy_images;
  const StrategyImages& b = *back.result.strategy_images;
  EXPECT_EQ(b.replicates, a.replicates);
  ASSERT_EQ(b.layers.size(), a.layers.size());
  for (std::size_t i = 0; i < a.layers.size(); ++i) {
    EXPECT_EQ(b.layers[i].s, a.layers[i].s);
    EXPECT_EQ(b.layers[i].t, a.layers[i].t);
    EXPECT_EQ(b.layers[i].image.values, a.layers[i].image.values);
  }
}

TEST(SavedRun, SomethingElseIsRefused) {
  EXPECT_ANY_THROW(read_saved_run("{\"format\": \"pcbench-saved-run\", \"version\": 2}"));
  EXPECT_ANY_THROW(read_saved_run("not json"));
}

class RunStoreInFolder : public ::testing::Test {
 protected:
  TemporaryFolder folder_;
  std::vector<RunPlan> plans_ = {plan_single("plain", "genz-gaussian", {}, 2000, 2),
                                 plan_single("lvc", "genz-gaussian", {}, 2000, 2)};
  std::ostringstream err_;

  // A journal in which the first plan finished.
  void save_first(std::uint64_t seed) {
    RunStore store = RunStore::start(folder_.path(), seed, "test", plans_, err_);
    store.save(plans_[0], execute_run(plans_[0], {.seed = seed}), err_);
  }
  std::string resume_error(std::uint64_t seed, const std::vector<RunPlan>& plans) {
    try {
      RunStore::resume(folder_.path(), seed, plans);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(RunStoreInFolder, RestoresWhatItSavedAndNothingElse) {
  save_first(5);
  RunStore store = RunStore::resume(folder_.path(), 5, plans_);
  const SavedRun* first = store.restore(plans_[0].id);
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(store.find(plans_[1].id), nullptr);
  EXPECT_EQ(store.restored(), 1u);
  const RunResult again = execute_run(plans_[0], {.seed = 5});
  EXPECT_EQ(first->result.replicates[1].estimate, again.replicates[1].estimate);
  store.discard(err_);
  EXPECT_FALSE(fs::exists(checkpoint_directory(folder_.path())));
  EXPECT_TRUE(err_.str().empty()) << err_.str();
}

TEST_F(RunStoreInFolder, RunsThatDidNotFinishAreNotSaved) {
  RunStore store = RunStore::start(folder_.path(), 1, "test", plans_, err_);
  RunResult not_run;
  store.save(plans_[0], not_run, err_);
  EXPECT_FALSE(fs::exists(store.file_of(plans_[0].id)));
}

TEST_F(RunStoreInFolder, ANewSessionRemovesAnEarlierJournalWithAWarning) {
  save_first(5);
  RunStore::start(folder_.path(), 5, "test", plans_, err_);
  EXPECT_NE(err_.str().find("warning"), std::string::npos);
  EXPECT_EQ(RunStore::resume(folder_.path(), 5, plans_).find(plans_[0].id), nullptr);
}

TEST_F(RunStoreInFolder, AnotherSeedIsBadInputNamingTheManifest) {
  save_first(5);
  const std::string message = resume_error(6, plans_);
  EXPECT_NE(message.find("session.json"), std::string::npos) << message;
  EXPECT_NE(message.find("seed 5"), std::string::npos) << message;
}

TEST_F(RunStoreInFolder, AnotherSuiteIsBadInputNamingTheRun) {
  save_first(5);
  const std::vector<RunPlan> other = {plans_[0], plan_single("lvc", "genz-gaussian", {}, 4000, 2)};
  const std::string message = resume_error(5, other);
  EXPECT_NE(message.find("run 2 was " + plans_[1].id), std::string::npos) << message;
  EXPECT_NE(resume_error(5, {plans_[0]}).find("this command plans 1"), std::string::npos);
}

TEST_F(RunStoreInFolder, ABadCheckpointIsBadInputNamingTheFile) {
  save_first(5);
  const fs::path file = checkpoint_directory(folder_.path()) / (plans_[0].id + ".json");
  write_text(file, "{\"truncated\": ");
  EXPECT_NE(resume_error(5, plans_).find(file.string()), std::string::npos);
  // A checkpoint of another seed (copied in by hand) is named too.
  write_text(file, saved_run_text(saved(plans_[0], 7)));
  EXPECT_NE(resume_error(5, plans_).find("saved with seed 7"), std::string::npos);
}

TEST_F(RunStoreInFolder, NoJournalIsBadInput) {
  EXPECT_NE(resume_error(1, plans_).find("no interrupted session"), std::string::npos);
  EXPECT_NE(resume_error(1, plans_).find("session.json"), std::string::npos);
}

struct CliResult {
  int status;
  std::string err;
};

CliResult cli(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int status = run_cli(args, out, err);
  return {status, err.str()};
}

TEST(CliResume, WithoutOutIsBadInput) {
  const CliResult r = cli({"run", "-e", "plain", "-i", "genz-gaussian", "--resume"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--resume needs --out"), std::string::npos) << r.err;
}

TEST(CliResume, WithExactOrEstimatesIsBadInput) {
  EXPECT_EQ(
      cli({"verify", "--exact", "-e", "pcbpt", "-i", "genz-gaussian", "--resume", "--out", "x"})
          .status,
      2);
  EXPECT_EQ(cli({"verify", "--estimates", "e.csv", "--reference", "1", "--resume"}).status, 2);
}

TEST_F(RunStoreInFolder, CliRefusesAnotherSeedAndWritesNothing) {
  const auto resume_with_seed = [&](const std::string& seed) {
    return cli({"run", "--resume", "--seed", seed, "-e", "plain,lvc", "-i", "genz-gaussian", "-n",
                "2000", "-r", "2", "-q", "--out", folder_.path().string()});
  };
  save_first(5);
  const std::vector<std::string> before = files_under(folder_.path());
  const CliResult r = resume_with_seed("6");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("session.json"), std::string::npos) << r.err;
  EXPECT_EQ(files_under(folder_.path()), before);
  // The same command with the journal's seed resumes: the first run is restored.
  const CliResult resumed = resume_with_seed("5");
  EXPECT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_EQ(files_under(folder_.path()), std::vector<std::string>{"report.json"});
}

}  // namespace
}  // namespace pcbench
