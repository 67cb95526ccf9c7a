#include "harness/run/runner.h"

#include "harness/run/scene_runner.h"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <exception>
#include <span>

#include <fmt/format.h>

#include "base/tally.h"
#include "harness/run/diagnostics.h"

namespace pcbench {

const char* to_string(RunStatus status) {
  switch (status) {
    case RunStatus::kOk:
      return "ok";
    case RunStatus::kInvalid:
      return "invalid";
    case RunStatus::kError:
      return "error";
    case RunStatus::kNotRun:
      return "not_run";
  }
  return "error";
}

namespace {

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double wall_seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// What one thread reuses across the chunks it runs.
struct ThreadState {
  std::unique_ptr<PathWorkspace> paths;
  EstimatorScratch scratch;
  std::vector<double> estimates;
  std::vector<double> magnitudes;
  Counters counters;
};

// The chunk's running sum at a series checkpoint that falls inside (or at the end of) it.
struct ChunkCheckpoint {
  std::uint64_t samples = 0;
  double sum = 0.0;
  double cpu_seconds = 0.0;
  double seconds = 0.0;
};

struct ChunkResult {
  Tally tally = Tally();
  CompensatedSum magnitude = {};  // Σ of per-sample estimates of ∫∫ |f|
  std::vector<ChunkCheckpoint> checkpoints = {};
  double seconds = 0.0;
  double cpu_seconds = 0.0;
  bool done = false;
};

}  // namespace

// How many of a replicate's largest |estimates| the tail fit gets: the PSIS tail 3√n plus its
// threshold, at most kMaxTailSize + 1. A higher threshold only moves the fit further into the
// tail; averaging over replicates keeps k̂ precise (sd about (1 + k) / √(256 R)), and keeping
// 3√n values per chunk cost the runner half its speed on cheap integrands.
namespace {
constexpr std::size_t kMaxTailSize = 256;
std::size_t kept_largest(std::uint64_t samples) {
  return std::min(pareto_tail_size(samples), kMaxTailSize) + 1;
}
}  // namespace

std::vector<std::uint64_t> series_checkpoints(std::uint64_t samples) {
  std::vector<std::uint64_t> out;
  for (std::uint64_t n = 1024; n < samples; n *= 2) out.push_back(n);
  out.push_back(samples);
  return out;
}

std::pair<std::uint32_t, std::uint32_t> replicate_range(const RunPlan& plan,
                                                        const RunnerOptions& options) {
  const std::uint32_t first = std::min(options.first_replicate, plan.replicates);
  const std::uint32_t count =
      options.replicate_count == 0 ? plan.replicates - first : options.replicate_count;
  return {first, std::min(plan.replicates, first + count)};
}

RunResult not_run_result(const RunPlan& plan, std::string why) {
  RunResult result;
  result.status = RunStatus::kNotRun;
  result.error = std::move(why);
  result.reference = plan.made_integrand->reference();
  return result;
}

void append_part(RunResult& run, RunResult&& part) {
  if (run.status == RunStatus::kOk && part.status != RunStatus::kOk) {
    run.status = part.status;
    run.error = std::move(part.error);
  }
  if (!run.first_nonfinite) run.first_nonfinite = part.first_nonfinite;
  run.wall_seconds += part.wall_seconds;
  run.counters.add(part.counters);
  for (auto& rep : part.replicates) run.replicates.push_back(std::move(rep));
  for (auto& image : part.images) run.images.push_back(std::move(image));
  add_strategy_images(run.strategy_images, std::move(part.strategy_images));
  for (const auto& counter : part.scene_counters) {
    const std::string& name = counter.first;
    const std::uint64_t count = counter.second;
    const auto same = std::find_if(run.scene_counters.begin(), run.scene_counters.end(),
                                   [&](const auto& c) { return c.first == name; });
    if (same == run.scene_counters.end()) {
      run.scene_counters.emplace_back(name, count);
    } else if (name == "scene_builds") {
      same->second = count;  // BVH builds so far in this process, not work of the part
    } else {
      same->second += count;
    }
  }
}

std::uint32_t chunk_size(std::uint64_t samples) {
  // At most 64 chunks per replicate keeps the merge cheap; at least 16 batches per chunk keeps
  // the per-chunk overhead small. Both depend on N only.
  const std::uint64_t per_chunk = std::max<std::uint64_t>(16 * kBatchSize, (samples + 63) / 64);
  const std::uint64_t rounded = (per_chunk + kBatchSize - 1) / kBatchSize * kBatchSize;
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(rounded, 1u << 30));
}

namespace {

// How a run's samples are cut into tasks: each replicate's N samples in chunks of chunk_size(N),
// for the replicates this process takes (replicate_range). Task t is chunk t % chunks_per_replicate
// of replicate first_replicate + t / chunks_per_replicate.
struct ChunkLayout {
  std::uint64_t samples = 0;
  std::uint32_t chunk = 0;
  std::uint64_t chunks_per_replicate = 0;
  std::uint32_t first_replicate = 0;
  std::uint32_t replicates = 0;
  std::uint64_t task_count() const { return chunks_per_replicate * replicates; }
};

ChunkLayout chunk_layout(const RunPlan& plan, const RunnerOptions& options) {
  ChunkLayout layout;
  layout.samples = plan.samples;
  layout.chunk = chunk_size(plan.samples);
  layout.chunks_per_replicate = (plan.samples + layout.chunk - 1) / layout.chunk;
  const auto [first, end] = replicate_range(plan, options);
  layout.first_replicate = first;
  layout.replicates = end - first;
  return layout;
}

// What every chunk of one analytic run reads.
struct ChunkJob {
  const Estimator& estimator;
  const Integrand& integrand;
  std::uint64_t key;  // the run's random streams (base/rng.h)
  ChunkLayout layout;
  const RunnerOptions& options;
};

// Runs one task (a chunk of one replicate) with this thread's reused state: its running tally,
// its Σ|f| and, at each series checkpoint inside it, its partial sum and times.
void run_chunk(const ChunkJob& job, std::uint64_t task, ThreadState& state, ChunkResult& out) {
  const ChunkLayout& layout = job.layout;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  if (!state.paths) state.paths = job.integrand.make_workspace();
  state.estimates.resize(kBatchSize);
  state.magnitudes.resize(kBatchSize);

  const auto replicate =
      layout.first_replicate + static_cast<std::uint32_t>(task / layout.chunks_per_replicate);
  const std::uint64_t first = (task % layout.chunks_per_replicate) * layout.chunk;
  const std::uint64_t end = std::min<std::uint64_t>(first + layout.chunk, layout.samples);
  for (std::uint64_t batch = first; batch < end; batch += kBatchSize) {
    BatchContext ctx{.key = job.key,
                     .replicate = replicate,
                     .first_sample = static_cast<std::uint32_t>(batch),
                     .sample_count = static_cast<std::uint32_t>(
                         std::min<std::uint64_t>(kBatchSize, end - batch)),
                     .counters = &state.counters};
    // The estimator's fast path where it has one (the same numbers), else its batch of
    // estimates, tallied here.
    if (!job.estimator.tally_batch(ctx, *state.paths, out.tally, out.magnitude)) {
      ctx.magnitudes = std::span<double>(state.magnitudes.data(), ctx.sample_count);
      const std::span<double> estimates(state.estimates.data(), ctx.sample_count);
      job.estimator.estimate_batch(ctx, *state.paths, state.scratch, estimates);
      std::size_t next = 0;
      out.tally.add_each(batch, ctx.sample_count, [&] { return estimates[next++]; });
      for (std::uint32_t i = 0; i < ctx.sample_count; ++i) out.magnitude.add(ctx.magnitudes[i]);
    }
    // Checkpoints are powers of two >= 1024 (multiples of the batch size) and N: they fall on
    // batch ends.
    const std::uint64_t done = batch + ctx.sample_count;
    if (done == layout.samples || (done >= 1024 && (done & (done - 1)) == 0)) {
      out.checkpoints.push_back({.samples = done,
                                 .sum = out.tally.sum(),
                                 .cpu_seconds = thread_cpu_seconds() - cpu_start,
                                 .seconds = wall_seconds_since(start)});
    }
  }
  out.cpu_seconds = thread_cpu_seconds() - cpu_start;
  out.seconds = wall_seconds_since(start);
  out.done = true;
  if (job.options.samples_done != nullptr) {
    job.options.samples_done->fetch_add(end - first, std::memory_order_relaxed);
  }
}

// Every task on TBB's threads, one task at a time (simple_partitioner); after Ctrl-C the tasks
// not yet started are skipped and stay not done.
void run_chunks(const ChunkJob& job, tbb::enumerable_thread_specific<ThreadState>& threads,
                std::vector<ChunkResult>& chunks) {
  const std::atomic<bool>* interrupted = job.options.interrupted;
  tbb::parallel_for(
      tbb::blocked_range<std::uint64_t>(0, job.layout.task_count(), 1),
      [&](const tbb::blocked_range<std::uint64_t>& range) {
        for (std::uint64_t task = range.begin(); task != range.end(); ++task) {
          if (interrupted != nullptr && interrupted->load()) continue;
          run_chunk(job, task, threads.local(), chunks[task]);
        }
      },
      tbb::simple_partitioner());
}

// One replicate from its chunks, merged in sample order: the same floating-point operations for
// any thread count.
ReplicateResult merged_replicate(std::span<const ChunkResult> parts, std::uint64_t samples) {
  Tally tally(kept_largest(samples));
  CompensatedSum magnitude;
  ReplicateResult rep;
  for (const ChunkResult& part : parts) {
    // The chunks before this one are complete: add this chunk's partial sums to theirs.
    for (const ChunkCheckpoint& point : part.checkpoints) {
      rep.checkpoints.push_back(
          {.samples = point.samples,
           .estimate = (tally.sum() + point.sum) / static_cast<double>(point.samples),
           .cpu_seconds = rep.cpu_seconds + point.cpu_seconds,
           .seconds = rep.seconds + point.seconds});
    }
    tally.merge(part.tally);
    magnitude.add(part.magnitude);
    rep.seconds += part.seconds;
    rep.cpu_seconds += part.cpu_seconds;
  }
  rep.estimate = tally.mean();
  rep.mean_abs = magnitude.value() / static_cast<double>(samples);
  rep.variance = tally.variance();
  rep.n = tally.count();
  rep.nonfinite = tally.nonfinite_count();
  rep.first_nonfinite_sample = tally.first_nonfinite_sample();
  rep.largest = tally.largest().sorted();
  rep.nonzero = tally.nonzero_count();
  rep.effective_samples = tally.effective_sample_size();
  if (!rep.largest.empty() && tally.sum_of_squares() > 0.0) {
    rep.largest_square_share = rep.largest.front() * rep.largest.front() / tally.sum_of_squares();
  }
  return rep;
}

// The replicates from the finished chunks, the first non-finite sample among them, and the
// status that follows: invalid when there is one.
void finish_replicates(const std::vector<ChunkResult>& chunks, const ChunkLayout& layout,
                       std::uint64_t seed, RunResult& result) {
  result.replicates.resize(layout.replicates);
  for (std::uint32_t r = 0; r < layout.replicates; ++r) {
    const std::span<const ChunkResult> parts(chunks.data() + r * layout.chunks_per_replicate,
                                             layout.chunks_per_replicate);
    ReplicateResult& rep = result.replicates[r] = merged_replicate(parts, layout.samples);
    if (rep.first_nonfinite_sample && !result.first_nonfinite) {
      result.first_nonfinite =
          NonfiniteLocation{seed, layout.first_replicate + r, *rep.first_nonfinite_sample};
    }
  }
  result.status = result.first_nonfinite ? RunStatus::kInvalid : RunStatus::kOk;
  if (result.first_nonfinite) {
    result.error =
        fmt::format("non-finite sample estimate (first at seed {}, replicate {}, sample {})", seed,
                    result.first_nonfinite->replicate, result.first_nonfinite->sample);
  }
}

// An analytic run's result before it runs: its reference (with |value| as the magnitude of a
// non-negative integrand) and whether its samples are independent.
RunResult result_before_running(const RunPlan& plan) {
  RunResult result;
  result.reference = plan.made_integrand->reference();
  if (plan.integrand->non_negative() && result.reference.kind != ReferenceKind::kNone) {
    result.reference.magnitude = std::fabs(result.reference.value);
  }
  result.independent_samples = plan.made_estimator->samples_independent();
  return result;
}

}  // namespace

RunResult execute_run(const RunPlan& plan, const RunnerOptions& options) {
  if (plan.render) return execute_scene_run(plan, options);
  RunResult result = result_before_running(plan);
  const auto run_start = std::chrono::steady_clock::now();
  const ChunkJob job{.estimator = *plan.made_estimator,
                     .integrand = *plan.made_integrand,
                     .key = run_key(options.seed, plan.stream_hash),
                     .layout = chunk_layout(plan, options),
                     .options = options};
  std::vector<ChunkResult> chunks;
  tbb::enumerable_thread_specific<ThreadState> threads;
  try {
    // Each chunk keeps as many of its largest |estimates| as the replicate's tail fit uses: the
    // replicate's largest are then among the union of its chunks'.
    chunks.assign(job.layout.task_count(),
                  ChunkResult{.tally = Tally(kept_largest(job.layout.samples))});
    run_chunks(job, threads, chunks);
  } catch (const std::exception& e) {
    result.status = RunStatus::kError;
    result.error = e.what();
    result.wall_seconds = wall_seconds_since(run_start);
    return result;
  }
  result.wall_seconds = wall_seconds_since(run_start);
  for (const ThreadState& state : threads) result.counters.add(state.counters);
  if (!std::all_of(chunks.begin(), chunks.end(), [](const ChunkResult& c) { return c.done; })) {
    result.status = RunStatus::kNotRun;
    result.error = "interrupted before the run finished";
    return result;
  }
  finish_replicates(chunks, job.layout, options.seed, result);
  return result;
}

}  // namespace pcbench
