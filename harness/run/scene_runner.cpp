#include "harness/run/scene_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>

#include "estimators/scene/render_replicate.h"
#include "integrands/scenes/scene_integrand.h"

namespace pcbench {
namespace {

// The scalar summary of one replicate's image, in the form analytic replicates have.
ReplicateResult summarise(const Image& image, std::uint64_t samples) {
  ReplicateResult r;
  double sum = 0.0, sum_abs = 0.0, sum_squares = 0.0, largest = 0.0;
  for (double v : image.values) {
    if (!std::isfinite(v)) {
      ++r.nonfinite;
      continue;
    }
    sum += v;
    sum_abs += std::fabs(v);
    sum_squares += v * v;
    largest = std::max(largest, std::fabs(v));
    if (v != 0.0) ++r.nonzero;
  }
  const double count = static_cast<double>(image.values.size());
  r.estimate = r.nonfinite ? std::nan("") : sum / count;
  r.mean_abs = sum_abs / count;
  r.n = samples;
  // Kish's effective count over pixel values: few bright pixels carrying the image mean show.
  r.effective_samples = sum_squares > 0.0 ? sum_abs * sum_abs / sum_squares : 0.0;
  r.largest_square_share = sum_squares > 0.0 ? largest * largest / sum_squares : 0.0;
  return r;
}

}  // namespace

RunResult execute_scene_run(const RunPlan& plan, const RunnerOptions& options) {
  RunResult result;
  result.reference = plan.made_integrand->reference();
  result.independent_samples = false;  // the pixels of an iteration share one light pool
  const auto start = std::chrono::steady_clock::now();
  const auto& integrand = dynamic_cast<const SceneIntegrand&>(*plan.made_integrand);
  const std::uint64_t key = run_key(options.seed, plan.stream_hash);
  scene::TraceCounters counters;
  try {
    const auto interrupted = [&] {
      return options.interrupted != nullptr && options.interrupted->load();
    };
    const auto [first_replicate, end_replicate] = replicate_range(plan, options);
    for (std::uint32_t r = first_replicate; r < end_replicate; ++r) {
      scene::ReplicateImage rendered = scene::render_replicate(
          integrand.scene(), *plan.render, key, r, static_cast<std::uint32_t>(plan.samples),
          options.interrupted, options.strategy_images);
      // A replicate cut short is no replicate: the run is reported as not run.
      if (interrupted()) {
        result.status = RunStatus::kNotRun;
        result.error = "interrupted";
        return result;
      }
      ReplicateResult rep = summarise(rendered.image, plan.samples);
      rep.seconds = rendered.seconds;
      rep.cpu_seconds = rendered.cpu_seconds;
      if (rep.nonfinite && !result.first_nonfinite) {
        result.first_nonfinite = NonfiniteLocation{.seed = options.seed, .replicate = r};
      }
      counters.add(rendered.counters);
      if (options.samples_done != nullptr) options.samples_done->fetch_add(plan.samples);
      result.replicates.push_back(std::move(rep));
      result.images.push_back(std::move(rendered.image));
      add_strategy_images(result.strategy_images, std::move(rendered.strategies));
    }
  } catch (const std::exception& e) {
    result.status = RunStatus::kError;
    result.error = e.what();
    return result;
  }
  const std::uint64_t pixels =
      integrand.scene().description().width * std::uint64_t{integrand.scene().description().height};
  result.counters.camera_paths = plan.render->traces_camera_paths(integrand.scene())
                                     ? pixels * plan.samples * result.replicates.size()
                                     : 0;
  result.counters.light_paths = counters.light_paths;
  result.counters.connections = counters.connections;
  result.scene_counters = {{"camera_rays", counters.camera_rays},
                           {"light_rays", counters.light_rays},
                           {"shadow_rays", counters.shadow_rays},
                           {"occluded", counters.occluded},
                           {"skipped_zero_value", counters.skipped_zero},
                           {"skipped_convex_enclosure", counters.skipped_convex},
                           {"splats", counters.splats},
                           {"scene_builds", scene_builds()}};
  result.status = RunStatus::kOk;
  for (const ReplicateResult& rep : result.replicates) {
    if (rep.nonfinite) result.status = RunStatus::kInvalid;
  }
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace pcbench
