#include "harness/run/equal_time.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcbench {
namespace {

// Analytic runs: 2 replicates × 8192 samples. A replicate's cpu_seconds is the thread CPU of its
// chunks summed, so every worker's share counts. N is in whole batches (the runner's unit of
// work) and at least 1024 (the first point of the convergence series).
constexpr PilotRule kAnalyticPilot{
    .samples = 8192, .step = kBatchSize, .least = 1024, .unit = "sample", .units = "samples"};

// Scenes: 2 replicates × 2 samples per pixel of the real image (a smaller image would measure
// another cost: the light pool, splats and tiles scale with the pixels). A scene replicate's
// cpu_seconds is process CPU over the replicate (estimators/scene/render_replicate.h), not
// thread CPU: the image renders on TBB's workers inside one call, whose thread CPU would be the
// calling thread's share alone. So the pilot measures with the clock its replicates report, and
// T means the same in both. Any N from 1 is a whole image; the limit is that of analytic runs
// (which also fits the renderer's 32-bit iteration count).
constexpr PilotRule kScenePilot{
    .samples = 2, .step = 1, .least = 1, .unit = "sample per pixel", .units = "samples per pixel"};
static_assert(kMaxSamples <= std::numeric_limits<std::uint32_t>::max(),
              "scene replicates count their iterations in 32 bits");

}  // namespace

const PilotRule& pilot_rule(const RunPlan& plan) {
  return plan.render ? kScenePilot : kAnalyticPilot;
}

std::uint64_t samples_for_seconds(const PilotRule& rule, double seconds, double cpu_per_sample) {
  if (!(cpu_per_sample > 0.0) || !std::isfinite(cpu_per_sample)) return rule.least;
  const double step = static_cast<double>(rule.step);
  const double steps = std::floor(seconds / cpu_per_sample / step);
  return static_cast<std::uint64_t>(
      std::clamp(steps * step, static_cast<double>(rule.least), static_cast<double>(kMaxSamples)));
}

RunPlan choose_samples(const RunPlan& plan, const RunnerOptions& options,
                       ProgressReporter& progress) {
  const PilotRule& rule = pilot_rule(plan);
  RunPlan pilot = with_samples(plan, rule.samples);
  pilot.replicates = 2;
  pilot.pilot = true;
  assign_id(pilot);
  // The run's options, but a pilot only measures the cost: no progress counter, no strategy
  // images (their buffers would cost time the run without them does not spend).
  RunnerOptions pilot_options = options;
  pilot_options.samples_done = nullptr;
  pilot_options.strategy_images = false;
  const RunResult result = execute_run(pilot, pilot_options);
  double cpu = 0.0;
  for (const ReplicateResult& rep : result.replicates) cpu += rep.cpu_seconds;
  const double per_sample = cpu / static_cast<double>(2 * rule.samples);
  const std::uint64_t samples = result.status == RunStatus::kOk
                                    ? samples_for_seconds(rule, *plan.seconds, per_sample)
                                    : rule.least;
  progress.message(fmt::format("pilot {} × {}: {:.3g} µs per {} -> {} {} for {} s",
                               plan.estimator->name, plan.integrand->name, 1e6 * per_sample,
                               rule.unit, samples, rule.units, *plan.seconds));
  RunPlan chosen = with_chosen_samples(plan, samples);
  chosen.pilot_samples = rule.samples;
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
