// From what the user asked for (suite rows, grids, command-line flags) to validated run plans.
//
// Everything that can be wrong with the input is found here, before any run starts: unknown
// estimator or integrand names, parameter keys read by neither, values of the wrong type, an
// expression that does not parse. Each error names its location and the valid choices.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimators/registry.h"
#include "integrands/registry.h"

namespace pcbench {

// The budget when nothing sets one, per integrand kind (default_samples).
inline constexpr std::uint64_t kDefaultSamples = 100000;        // analytic: samples
inline constexpr std::uint64_t kDefaultScenePixelSamples = 16;  // scene: samples per pixel
inline constexpr std::uint32_t kDefaultReplicates = 32;
inline constexpr std::uint64_t kDefaultSeed = 1;
// Counter layout limits of the random streams (base/rng.h).
inline constexpr std::uint64_t kMaxSamples = 0xFFFFFFFFull;
inline constexpr std::uint32_t kMaxReplicates = 0xFFFFFFu;
// 10^13 camera samples would take weeks here; a budget beyond it is a typo.
inline constexpr double kMaxTotalSamples = 1e13;
// Runs one invocation may plan (the default suite has 113). A grid is a product, so a few
// hundred bytes of lists ask for 10^9 runs: refused while expanding, before its plans fill memory.
inline constexpr std::size_t kMaxRuns = 100000;

// A grid: the product of its lists. A plain suite row is a grid whose lists have one element.
struct GridRequest {
  std::vector<std::string> estimators = {};
  std::vector<std::string> integrands = {};
  std::map<std::string, std::vector<std::string>> params = {};  // key -> values, as text
  std::optional<std::uint64_t> samples = {};
  std::optional<double> seconds = {};  // an equal-time budget instead of samples
  std::optional<std::uint32_t> replicates = {};
  std::optional<std::string> expect = {};
  std::string where = {};  // "suites/x.json: /grid/0" or "command line"
};

// A grid with its names looked up in the registries: the one place a name is resolved. What
// comes after (splitting --param values, expanding, planning, running) uses these entries.
struct ResolvedGrid {
  std::vector<const EstimatorEntry*> estimators = {};
  std::vector<const IntegrandEntry*> integrands = {};
  // Params, budget, expect and where; its name lists are the ones resolved above.
  GridRequest request = {};
};

// Looks each name of `grid` up once; InputError naming grid.where, the unknown name and the
// valid ones.
ResolvedGrid resolve_names(GridRequest grid);

// Budget settings that apply unless a row sets its own; `forced` values (from the command line)
// override rows too.
struct BudgetDefaults {
  // Unset: the default of the integrand's kind (default_samples), so that an explicit 100000 is
  // 100000 on a scene too.
  std::optional<std::uint64_t> samples = {};
  std::uint32_t replicates = kDefaultReplicates;
  std::optional<std::uint64_t> forced_samples = {};
  std::optional<std::uint32_t> forced_replicates = {};
  std::optional<double> seconds = {};  // a suite's default equal-time budget
  std::optional<double> forced_seconds = {};
};

// An equal-time budget is at most this many CPU seconds per replicate.
inline constexpr double kMaxSecondsPerReplicate = 1e6;
// And at least this much: below a millisecond a replicate measures the clock, not the estimator.
inline constexpr double kMinSecondsPerReplicate = 1e-3;

struct RunPlan {
  // The run as requested: 16 hex digits of a hash of estimator, integrand, effective params,
  // budget (samples, or seconds) and replicates.
  std::string id;
  // The hash of `id`, except for an equal-time run once its sample count is chosen, which takes
  // the id of the same run with `--samples N`, so that the replay gives the same numbers.
  std::uint64_t id_hash = 0;
  // Keys the random streams (run_key): id_hash, except for a run with paired streams.
  std::uint64_t stream_hash = 0;
  // Paired streams (a suite's "paired": true, --paired; scene runs only): the streams are keyed
  // by the scene, its params, the samples and the replicates instead of the run, so that the
  // runs of two estimators on one scene trace the same camera paths and light pools replicate by
  // replicate, and their images are compared on replicate differences (paired t,
  // harness/verify/block_pyramid.h). Replicate r of one run is still independent of replicate
  // r' != r of every run, which is what the paired test needs. The id says "paired" too, so a
  // paired run never takes an unpaired run's journal entry.
  bool paired_streams = false;
  std::string where;
  const EstimatorEntry* estimator = nullptr;
  const IntegrandEntry* integrand = nullptr;
  ResolvedParams estimator_params;
  ResolvedParams integrand_params;
  std::uint64_t samples = 0;  // 0 for an equal-time run until its pilot has chosen N
  std::uint32_t replicates = 0;
  // The run's samples over all its replicates: its work, for progress and limits (0 for an
  // equal-time run until its pilot has chosen N).
  std::uint64_t total_samples() const { return samples * replicates; }
  // Equal time: CPU seconds per replicate (an analytic replicate's thread CPU summed over its
  // chunks, a scene replicate's process CPU: all threads either way; harness/run/equal_time.h). A
  // short pilot measures the cost per sample (per pixel, for a scene); the run then takes a
  // fixed N from it (never stopping on a clock mid-way, which would bias estimators whose cost
  // correlates with their value).
  std::optional<double> seconds;
  // An equal-time pilot: its id differs from every real run's, so that it never takes the
  // numbers of the run it measures (a pilot of 2 replicates × N would otherwise be that run).
  bool pilot = false;
  std::uint64_t pilot_samples = 0;                  // per pilot replicate (2 replicates)
  double pilot_cpu_per_sample = 0.0;                // what the pilot measured
  std::optional<std::string> expect;                // unset: "consistent" if there is a reference
  std::shared_ptr<const Estimator> made_estimator;  // analytic integrands
  // Scenes (made_integrand is a SceneIntegrand).
  std::shared_ptr<const scene::SceneEstimator> render;
  std::shared_ptr<const Integrand> made_integrand;
};

// The samples of a run whose row, suite and command line set none: kDefaultSamples on an
// analytic integrand, kDefaultScenePixelSamples per pixel on a scene.
std::uint64_t default_samples(const IntegrandEntry& integrand);

// Expands every grid, resolves and builds each row, and collapses rows with the same id (the
// first occurrence stays). Throws InputError on the first bad input.
std::vector<RunPlan> plan_runs(const std::vector<ResolvedGrid>& grids,
                               const BudgetDefaults& budget);
// The same for grids not resolved yet (suite files, calibrations, tests): resolve_names, then
// plan_runs.
std::vector<RunPlan> plan_runs(const std::vector<GridRequest>& grids, const BudgetDefaults& budget);

// Sets plan.id_hash and plan.id from its estimator, integrand, effective params and budget.
void assign_id(RunPlan& plan);

// The same run with another budget of samples: a new id, so new random numbers (sequential
// escalation, pilots).
RunPlan with_samples(const RunPlan& plan, std::uint64_t samples);

// An equal-time run with its sample count chosen: keeps the requested id, and takes the random
// streams of `--samples samples` (see RunPlan::id_hash).
RunPlan with_chosen_samples(const RunPlan& plan, std::uint64_t samples);

// Pairs the streams of every scene run in `plans` (RunPlan::paired_streams), with new ids;
// analytic runs keep theirs (they are tested against exact values, and their pairwise
// comparisons are Welch's, which needs independent runs).
void pair_scene_streams(std::vector<RunPlan>& plans);

// Whether runs a and b trace the same random streams replicate by replicate (then they have the
// same samples and replicates too): their comparison must be paired, not Welch's.
inline bool share_streams(const RunPlan& a, const RunPlan& b) {
  return a.paired_streams && b.paired_streams && a.stream_hash == b.stream_hash;
}

// The id of a run: a hash of estimator, integrand, effective params, samples and replicates.
std::uint64_t run_id_hash(const std::string& estimator, const std::string& integrand,
                          const std::map<std::string, std::string>& effective_params,
                          std::uint64_t samples, std::uint32_t replicates);

extern const std::vector<std::string> kExpectations;  // consistent, biased, inconclusive

// The one rule for what a test of `plan` is expected to find, sampled runs and `--exact` checks
// alike: the row's `expect` if given; else "inconclusive" when the test cannot decide
// (`decidable` false: no reference, a t-test on an infinite-variance integrand, no resampling
// step to enumerate); else "biased" for a negative control; else "consistent".
std::string expected_result(const RunPlan& plan, bool decidable);

}  // namespace pcbench
