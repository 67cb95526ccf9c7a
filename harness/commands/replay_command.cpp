#include "harness/commands/replay_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>

#include "base/errors.h"
#include "harness/commands/command_line_grid.h"
#include "harness/run/replay.h"

namespace pcbench {

CLI::App* add_replay_command(CLI::App& app, ReplayArguments& args) {
  CLI::App* replay = app.add_subcommand(
      "replay",
      "re-evaluate one camera sample of a run with its random streams (the command a run with a "
      "non-finite sample prints)");
  replay->add_option("--estimator,-e", args.estimators, "the run's estimator")->required();
  replay->add_option("--integrand,-i", args.integrands, "the run's integrand")->required();
  replay->add_option("--param,-p", args.params, "key=value, repeatable: the run's parameters");
  replay->add_option("--samples,-n", args.samples, "the run's camera samples per replicate")
      ->check(CLI::Range(std::uint64_t{1}, kMaxSamples));
  replay->add_option("--replicates,-r", args.replicates, "the run's replicates")
      ->check(CLI::Range(std::uint32_t{2}, kMaxReplicates));
  add_seed_option(replay, args.seed, "the run's seed (default 1)");
  replay->add_option("--replicate", args.replicate, "the replicate (0-based)")->required();
  replay->add_option("--sample", args.sample, "the camera sample within it (0-based)")->required();
  replay->add_option("--run-id", args.run_id,
                     "refuse unless the options rebuild this run id (16 hex digits)");
  replay->add_flag("--json", args.json, "print as JSON (non-finite numbers as \"nan\", \"inf\")");
  return replay;
}

int replay_command(const ReplayArguments& args, const CommandContext& context) {
  const ResolvedGrid grid = command_line_grid(args.estimators, args.integrands, args.params);
  BudgetDefaults budget;
  if (context.app.count("--samples")) budget.forced_samples = args.samples;
  if (context.app.count("--replicates")) budget.forced_replicates = args.replicates;
  const std::vector<RunPlan> plans = plan_runs({grid}, budget);
  if (plans.size() != 1) {
    throw InputError(
        fmt::format("command line: replay takes one run; these options plan {}", plans.size()));
  }
  return run_replay(plans[0], args.seed, args.replicate, args.sample, args.run_id, args.json,
                    context.out);
}

}  // namespace pcbench
