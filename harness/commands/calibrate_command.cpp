#include "harness/commands/calibrate_command.h"

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <algorithm>

#include "base/errors.h"
#include "harness/commands/calibration.h"
#include "harness/commands/command_line_grid.h"
#include "harness/commands/tile_calibration.h"

namespace pcbench {
namespace {

// The calibration's parameters, parsed as `run` parses them but one value per key: a
// calibration is of one configuration (a grid would be several calibrations).
ParamText calibrate_params(const std::vector<std::string>& flags,
                           const std::vector<std::string>& estimators,
                           const std::vector<std::string>& integrands) {
  const ResolvedGrid grid =
      resolve_names({.estimators = estimators, .integrands = integrands, .where = "command line"});
  ParamText params;
  for (const auto& [key, values] : params_from_flags(flags, grid)) {
    if (values.size() != 1) {
      throw InputError(fmt::format(
          "command line: calibrate takes one value per --param; '{}' has {}", key, values.size()));
    }
    params[key] = values.front();
  }
  return params;
}

// Scenes (the block pyramid) or one analytic integrand (the run test); returns how many scenes.
std::size_t checked_scene_count(const CalibrateArguments& args) {
  const std::size_t scenes = static_cast<std::size_t>(
      std::count_if(args.integrands.begin(), args.integrands.end(), is_scene_name));
  if (scenes > 0 && scenes < args.integrands.size()) {
    throw InputError(
        "command line: calibrate takes scenes (the block pyramid) or one analytic integrand (the "
        "run test), not both");
  }
  if (scenes == 0 && args.integrands.size() > 1) {
    throw InputError("command line: calibrate takes one analytic integrand");
  }
  if (scenes == 0 && args.paired) {
    throw InputError(
        "command line: --paired pairs scene runs; calibrate on an analytic integrand takes no "
        "--paired (give scenes with --integrand)");
  }
  return scenes;
}

}  // namespace

CLI::App* add_calibrate_command(CLI::App& app, CalibrateArguments& args) {
  CLI::App* calibrate = app.add_subcommand(
      "calibrate",
      "the verifier's self-test: p-values of unbiased estimators over many seeds are uniform, "
      "false alarms match alpha, and the power curve follows its prediction (on scenes: of the "
      "block pyramid, overall and per scale)");
  calibrate
      ->add_option("--estimator,-e", args.estimators,
                   "unbiased estimators to calibrate (default plain,vc-all,lvc,pcbpt; on scenes "
                   "pt,plain)")
      ->delimiter(',');
  calibrate
      ->add_option("--integrand,-i", args.integrands,
                   "integrand with an exact reference (default genz-gaussian), or scenes: the "
                   "block pyramid against the exact image (furnace) and between estimators "
                   "(others)")
      ->delimiter(',');
  calibrate->add_option(
      "--param,-p", args.params,
      "key=value for the estimators and the integrand (resolution, ...), repeatable");
  calibrate
      ->add_option("--samples,-n", args.samples,
                   "samples per replicate (default 1000; on scenes samples per pixel, 4)")
      ->check(CLI::Range(std::uint64_t{1}, kMaxSamples));
  calibrate
      ->add_option("--replicates,-r", args.replicates,
                   "replicates per run (default 16; on scenes 8 images)")
      ->check(CLI::Range(std::uint32_t{2}, kMaxReplicates));
  calibrate
      ->add_option("--seeds", args.seeds,
                   "seeds (runs) per estimator (default 200; on scenes 1000)")
      ->check(CLI::Range(std::uint32_t{20}, std::uint32_t{1000000}));
  add_seed_and_threads_options(calibrate, args.seed, args.threads);
  calibrate->add_option("--out,-o", args.out_dir,
                        "output folder (default results/runs/<date-time>/)");
  calibrate->add_flag("--quiet,-q", args.quiet, "no table");
  calibrate->add_flag("--paired", args.paired,
                      "scenes: runs share their random streams and pairs are tested on replicate "
                      "differences (the paired design of run --paired)");
  return calibrate;
}

int calibrate_command(const CalibrateArguments& args, const CommandContext& context) {
  const std::size_t scenes = checked_scene_count(args);
  const bool given_seed = context.app.count("--seed") > 0;
  prepare_out_dir(args.out_dir, context.app.count("--out") > 0);
  const SessionOptions session = session_options(args, context);
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, session.threads);
  // What both self-tests take from the command line alike.
  const auto take_common = [&](auto& options) {
    if (!args.estimators.empty()) options.estimators = args.estimators;
    if (args.samples > 0) options.samples = args.samples;
    if (args.replicates > 0) options.replicates = args.replicates;
    if (args.seeds > 0) options.seeds = args.seeds;
    if (given_seed) options.first_seed = args.seed;
    options.interrupted = context.interrupted;
  };
  if (scenes > 0) {
    TileCalibrationOptions options;
    options.scenes = args.integrands;
    options.paired = args.paired;
    take_common(options);
    options.params = calibrate_params(args.params, options.estimators, options.scenes);
    return run_tile_calibration(options, session, context.out, context.err);
  }
  CalibrationOptions options;
  if (!args.integrands.empty()) options.integrand = args.integrands.front();
  take_common(options);
  options.params = calibrate_params(args.params, options.estimators, {options.integrand});
  return run_calibration(options, session, context.out, context.err);
}

}  // namespace pcbench
