// One invocation of `pcbench run`: execute the planned runs in order, test them as one family,
// write the report atomically, print the summary and decide the exit status.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/plan/scale_requirements.h"
#include "harness/run/replicate_farm.h"
#include "harness/run/run_store.h"
#include "harness/verify/reference_cache.h"
#include "harness/verify/statistics.h"

namespace pcbench {

inline constexpr std::uint32_t kMaxStages = 3;
inline constexpr std::uint64_t kEscalationFactor = 4;
// A stage is borderline when not rejected but its (adjusted) p-value is within this factor of
// the threshold it was compared with.
inline constexpr double kBorderlineFactor = 10.0;

// Exit statuses (docs/reference/INTERFACE.md).
enum ExitStatus : int {
  kExitOk = 0,
  kExitVerdictDiffers = 1,
  kExitBadInput = 2,
  kExitRunFailed = 3,
  // verify --images --fail-underpowered: every verdict as expected, but the comparison's test
  // misses a scale's power requirement (docs/reference/INTERFACE.md).
  kExitUnderpowered = 4,
  kExitInterrupted = 130
};

struct SessionOptions {
  std::string suite_name = "command line";
  std::uint64_t seed = kDefaultSeed;
  unsigned threads = 0;
  std::optional<std::string> out_dir;  // default: results/runs/<date-time>/ + results/latest
  bool quiet = false;
  double alpha = kDefaultAlpha;   // family-wise
  bool compare_pairwise = false;  // the suite's "compare": "pairwise"
  // Sequential escalation (verify): a borderline or low-count run is run again with
  // kEscalationFactor times the samples, up to kMaxStages stages in all. Half of alpha goes to
  // the first stage (Holm), half is split evenly (Bonferroni) over every possible later stage
  // of every run, so the family-wise false-alarm rate stays below alpha whatever is escalated.
  bool escalate = false;
  // Runs on one integrand take their replicates in turn (harness/run/interleaved_runs.h), so that
  // their efficiency ratios compare them under the same machine load.
  bool interleave = false;
  // Scene runs also write the mean image of each (s, t) strategy
  // (harness/verify/strategy_image_file.h).
  bool strategy_images = false;
  // Scene runs also write each replicate image (images/<id>_rep<k>.exr), for other tools and
  // for `verify --images`.
  bool replicate_images = false;
  // What each scale of a scene comparison's block pyramid must detect (a suite's "require_mdb",
  // --require-mdb).
  ScaleRequirements scale_requirements = {};
  std::vector<std::string> argv;
  const std::atomic<bool>* interrupted = nullptr;
  // `--resume`: the interrupted session's journal, already checked against the plans. Its done
  // runs are restored instead of run; without it a session starts a new journal in its folder.
  std::shared_ptr<RunStore> resume;
  // Converged scene images for the errors of scene runs (harness/verify/reference_cache.h); read
  // only.
  std::filesystem::path reference_cache = kDefaultReferenceCache;
  // Rank 0 of an MPI job: the runs' replicates are computed over all ranks (pilots and
  // interleaved runs stay on rank 0); null in one process.
  ReplicateFarm* farm = nullptr;
  // A `--shard` run (harness/session/shard.h): the runs are saved to the journal and kept there,
  // and nothing is tested or reported (`pcbench merge` does both for all shards).
  bool journal_only = false;
};

// The runner's options of a session, built once (seed, interrupt flag, strategy images) and
// passed down; a run's variations (its progress counter, a pilot, one replicate on a rank of an
// MPI job) are copies of it with that field set.
RunnerOptions runner_options(const SessionOptions& options);

// Runs `plans` as one session, in named steps: choose budgets (equal-time pilots) and execute
// (interleaved, over an MPI farm, or one by one; harness/session/execution.h), test the family
// and escalate (harness/session/family_test.h), publish the report (session.cpp). Returns the
// exit status.
int run_session(const std::vector<RunPlan>& plans, const SessionOptions& options, std::ostream& out,
                std::ostream& err);

// `pcbench verify --exact`: the enumerated check of each plan's resampling step
// (harness/verify/exact_check.h) instead of sampled runs. Exit 0 when every check matches its
// expectation (a negative control must come out biased), 1 otherwise.
int run_exact_session(const std::vector<RunPlan>& plans, const SessionOptions& options,
                      std::ostream& out, std::ostream& err);

}  // namespace pcbench
