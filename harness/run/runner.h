// Runs one plan: R replicates × N camera samples, in parallel over fixed chunks of samples.
//
// The chunking depends only on N, never on the thread count, and chunk tallies are merged in
// sample order, so the numbers are bitwise identical for any number of threads.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "harness/plan/plan.h"
#include "integrands/integrand.h"
#include "results/image.h"
#include "results/strategy_images.h"

namespace pcbench {

enum class RunStatus { kOk, kInvalid, kError, kNotRun };
const char* to_string(RunStatus status);

// A replicate's running estimate after its first `samples` samples (a point of the convergence
// series), with the thread CPU and wall time its chunks had spent by then.
struct Checkpoint {
  std::uint64_t samples = 0;
  double estimate = 0.0;
  double cpu_seconds = 0.0;
  double seconds = 0.0;
};

// Where the convergence series is taken: every power of two from 1024 below N, and N.
std::vector<std::uint64_t> series_checkpoints(std::uint64_t samples);

struct ReplicateResult {
  double estimate = 0.0;  // mean of the N per-sample estimates (non-finite ones included)
  double variance = 0.0;  // sample variance of the per-sample estimates
  double mean_abs = 0.0;  // the estimator's estimate of ∫∫ |f|
  std::uint64_t n = 0;
  std::uint64_t nonfinite = 0;
  std::optional<std::uint64_t> first_nonfinite_sample = {};
  double seconds = 0.0;               // wall time of this replicate's chunks, summed
  double cpu_seconds = 0.0;           // thread CPU time of this replicate's chunks, summed
  std::vector<double> largest = {};   // the largest |per-sample estimates| (as many as the tail fit
                                      // uses: harness/run/diagnostics.h), largest first
  std::uint64_t nonzero = 0;          // finite samples != 0
  double effective_samples = 0.0;     // Kish's (Σ |x|)² / Σ x² over the finite samples
  double largest_square_share = 0.0;  // (largest |x|)² / Σ x²: near 1/n unless one sample rules
  std::vector<Checkpoint> checkpoints = {};  // at series_checkpoints(N), in order
};

struct NonfiniteLocation {
  std::uint64_t seed = 0;
  std::uint32_t replicate = 0;
  std::uint64_t sample = 0;
};

struct RunResult {
  RunStatus status = RunStatus::kNotRun;
  std::string error;
  Reference reference;
  std::vector<ReplicateResult> replicates;
  Counters counters;
  double wall_seconds = 0.0;
  std::optional<NonfiniteLocation> first_nonfinite;
  // False where the samples of a replicate share a pool: the within-replicate variance is then
  // not an estimate of anything useful and is not reported.
  bool independent_samples = true;
  // Scenes: each replicate's image, and the tracing counters (rays by kind, connections
  // occluded or skipped and why) by name.
  std::vector<Image> images = {};
  std::vector<std::pair<std::string, std::uint64_t>> scene_counters = {};
  // Scenes with RunnerOptions::strategy_images: the replicates' images split by strategy.
  std::optional<StrategyImages> strategy_images = {};
};

struct RunnerOptions {
  std::uint64_t seed = kDefaultSeed;
  const std::atomic<bool>* interrupted = nullptr;  // polled between chunks
  // Samples finished so far, summed over replicates (for the progress line); may be null.
  std::atomic<std::uint64_t>* samples_done = nullptr;
  // Only replicates [first_replicate, first_replicate + replicate_count) (all from the first
  // when the count is 0), as interleaved runs take them: each replicate's numbers depend only on
  // its index, so a run taken in parts is the run taken whole.
  std::uint32_t first_replicate = 0;
  std::uint32_t replicate_count = 0;
  // Scenes: also gather each (s, t) strategy's image (`--strategy-images`; costs a buffer per
  // strategy). The run's numbers are the same either way.
  bool strategy_images = false;
};

// The chunk (unit of parallel work, a multiple of kBatchSize) for N samples.
std::uint32_t chunk_size(std::uint64_t samples);

RunResult execute_run(const RunPlan& plan, const RunnerOptions& options);

// The result of a run that did not run (an interrupt came first), saying why.
RunResult not_run_result(const RunPlan& plan, std::string why);

// The replicates of `options` (all of the plan's by default): [first, end).
std::pair<std::uint32_t, std::uint32_t> replicate_range(const RunPlan& plan,
                                                        const RunnerOptions& options);

// Appends a later part of the same run (its next replicates) to `run`: replicates, images,
// counters and times; the first non-finite sample and a failure are kept from whichever part
// had them first.
void append_part(RunResult& run, RunResult&& part);

}  // namespace pcbench
