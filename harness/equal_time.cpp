#include "harness/equal_time.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace pcbench {
namespace {

// A pilot of 2 replicates × kPilotSamples measures the thread CPU seconds per sample; N =
// seconds / that, in whole batches, at least 1024.
constexpr std::uint64_t kPilotSamples = 8192;

}  // namespace

RunPlan choose_samples(const RunPlan& plan, const RunnerOptions& options,
                       ProgressReporter& progress) {
  RunPlan pilot = with_samples(plan, kPilotSamples);
  pilot.replicates = 2;
  pilot.pilot = true;
  assign_id(pilot);
  const RunResult result =
      execute_run(pilot, {.seed = options.seed, .interrupted = options.interrupted});
  double cpu = 0.0;
  for (const ReplicateResult& rep : result.replicates) cpu += rep.cpu_seconds;
  const double per_sample = cpu / static_cast<double>(2 * kPilotSamples);
  std::uint64_t samples = 1024;
  if (result.status == RunStatus::kOk && per_sample > 0.0) {
    const double batches = std::floor(*plan.seconds / per_sample / kBatchSize);
    samples = static_cast<std::uint64_t>(
        std::clamp(batches * kBatchSize, 1024.0, static_cast<double>(kMaxSamples)));
  }
  progress.message(fmt::format("pilot {} × {}: {:.3g} µs per sample -> {} samples for {} s",
                               plan.estimator->name, plan.integrand->name, 1e6 * per_sample,
                               samples, *plan.seconds));
  RunPlan chosen = with_chosen_samples(plan, samples);
  chosen.pilot_samples = kPilotSamples;
  chosen.pilot_cpu_per_sample = per_sample;
  return chosen;
}

RunPlan restored_choice(const RunPlan& plan, const SavedRun& saved) {
  RunPlan chosen = with_chosen_samples(plan, saved.samples);
  chosen.pilot_samples = saved.pilot_samples;
  chosen.pilot_cpu_per_sample = saved.pilot_cpu_per_sample;
  return chosen;
}

}  // namespace pcbench
