#include "harness/commands/reference_command.h"

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <cmath>

#include "base/errors.h"
#include "base/text_hash.h"
#include "harness/commands/command_line_grid.h"
#include "harness/run/scene_runner.h"
#include "harness/session/session.h"
#include "harness/verify/image_statistics.h"
#include "harness/verify/reference_cache.h"
#include "integrands/scenes/scene_integrand.h"
#include "results/context.h"

namespace pcbench {
namespace {

const SceneIntegrand& checked_scene(const RunPlan& plan) {
  const auto* scene = dynamic_cast<const SceneIntegrand*>(plan.made_integrand.get());
  const std::string what =
      fmt::format("command line: {} × {}", plan.estimator->name, plan.integrand->name);
  if (!plan.render || !scene) {
    throw InputError(fmt::format("{}: a reference image is made of a scene only", what));
  }
  if (plan.estimator->biased) {
    throw InputError(fmt::format("{}: a negative control makes no reference", what));
  }
  if (!plan.render->samples_all_paths(scene->scene())) {
    throw InputError(fmt::format(
        "{}: this estimator cannot sample every light-carrying path of the scene; use plain, "
        "vc-all, lvc or pcbpt",
        what));
  }
  return *scene;
}

constexpr std::uint64_t kDefaultReferenceSamples = 256;
constexpr std::uint32_t kDefaultReferenceReplicates = 8;

}  // namespace

int run_reference_command(const std::vector<RunPlan>& plans, const ReferenceOptions& options,
                          std::ostream& out, std::ostream& err) {
  for (const RunPlan& plan : plans) checked_scene(plan);  // all checked before any work
  const ReferenceCache cache(options.cache);
  const Context context = gather_context(options.argv, options.runner.seed, 0);
  int status = kExitOk;
  for (const RunPlan& plan : plans) {
    const scene::SceneDescription& scene = checked_scene(plan).scene().description();
    err << fmt::format("rendering {} {}x{} with {}: {} spp × {} replicates\n", plan.integrand->name,
                       scene.width, scene.height, plan.estimator->name, plan.samples,
                       plan.replicates);
    // Streams of their own: a reference must be independent of every run measured against it,
    // even a run of the same estimator with the same budget and seed.
    RunPlan own = plan;
    own.id_hash = fnv1a(plan.id_hash, "reference-image");
    own.stream_hash = own.id_hash;
    own.paired_streams = false;
    const RunResult result = options.farm != nullptr ? options.farm->run(own, options.runner)
                                                     : execute_scene_run(own, options.runner);
    if (result.status != RunStatus::kOk) {
      err << fmt::format("pcbench: {} × {}: no reference ({}{})\n", plan.estimator->name,
                         plan.integrand->name, to_string(result.status),
                         result.error.empty() ? "" : ": " + result.error);
      status = result.status == RunStatus::kNotRun ? kExitInterrupted : kExitRunFailed;
      if (status == kExitInterrupted) return status;
      continue;
    }
    const PixelStatistics stats = pixel_statistics(result.images);
    double cpu = 0.0;
    for (const ReplicateResult& rep : result.replicates) cpu += rep.cpu_seconds;
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& [key, value] : plan.estimator_params.values()) params[key] = to_text(value);
    const ReferenceImage image{
        .mean = stats.mean,
        .standard_error = stats.standard_error,
        .provenance = {{"estimator", plan.estimator->name},
                       {"estimator_params", params},
                       {"samples_per_pixel", plan.samples},
                       {"replicates", plan.replicates},
                       {"seed", options.runner.seed},
                       {"cpu_seconds", cpu},
                       {"date", context.date},
                       {"version", context.version},
                       {"git_commit", context.git_commit},
                       {"git_dirty", context.git_dirty == "unknown"
                                         ? nlohmann::ordered_json(nullptr)
                                         : nlohmann::ordered_json(context.git_dirty == "true")}}};
    const bool stored = cache.store(scene, image, err);
    const double quality = relative_variance(stats.mean, stats.standard_error);
    out << fmt::format(
        "{} {}x{} L={} with {}: {} spp × {} replicates, {:.1f} CPU s, relative standard error "
        "{:.3g}% -> {}{}\n",
        plan.integrand->name, scene.width, scene.height, scene.max_length, plan.estimator->name,
        plan.samples, plan.replicates, cpu, 100.0 * std::sqrt(quality),
        cache.image_path(scene).string(),
        stored ? "" : " (kept the cached image: it is at least as converged)");
  }
  return status;
}

CLI::App* add_reference_command(CLI::App& app, ReferenceArguments& args) {
  CLI::App* reference = app.add_subcommand(
      "reference",
      "render converged images of scenes into the reference cache, for the errors (RMSE, "
      "relative MSE, equal time) of later scene runs");
  reference->add_option("--integrand,-i", args.integrands, "scene(s); a comma list renders each")
      ->required()
      ->delimiter(',');
  reference->add_option("--estimator,-e", args.estimators, "estimator (default plain: BDPT)")
      ->delimiter(',');
  reference->add_option("--param,-p", args.params,
                        "key=value, repeatable (resolution, max_length, …)");
  reference
      ->add_option("--samples,-n", args.samples, "samples per pixel per replicate (default 256)")
      ->check(CLI::Range(std::uint64_t{1}, kMaxSamples));
  reference
      ->add_option("--replicates,-r", args.replicates,
                   "replicates, for the image's standard error (default 8)")
      ->check(CLI::Range(std::uint32_t{2}, kMaxReplicates));
  add_seed_and_threads_options(reference, args.seed, args.threads);
  add_reference_cache_option(reference, args.reference_cache);
  return reference;
}

int reference_command(const ReferenceArguments& args, const CommandContext& context) {
  const std::vector<std::string> estimators =
      args.estimators.empty() ? std::vector<std::string>{"plain"} : args.estimators;
  const ResolvedGrid grid = command_line_grid(estimators, args.integrands, args.params);
  BudgetDefaults budget;
  budget.forced_samples = args.samples > 0 ? args.samples : kDefaultReferenceSamples;
  budget.forced_replicates = args.replicates > 0 ? args.replicates : kDefaultReferenceReplicates;
  const std::vector<RunPlan> plans = plan_runs({grid}, budget);
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  thread_count(args.threads));
  if (this_rank() != 0) return serve_replicates(plans, context.interrupted);
  return run_reference_command(plans,
                               {.runner = {.seed = args.seed, .interrupted = context.interrupted},
                                .cache = args.reference_cache,
                                .argv = context.argv,
                                .farm = replicate_farm(plans)},
                               context.out, context.err);
}

}  // namespace pcbench
