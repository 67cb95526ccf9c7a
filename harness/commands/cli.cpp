#include "harness/commands/cli.h"

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>

#include "base/comma_list.h"
#include "base/errors.h"
#include "harness/commands/calibrate_command.h"
#include "harness/commands/command_line_grid.h"
#include "harness/commands/command_options.h"
#include "harness/commands/compare_command.h"
#include "harness/commands/external_verify.h"
#include "harness/commands/image_set_verify.h"
#include "harness/commands/list_command.h"
#include "harness/commands/merge_command.h"
#include "harness/commands/plot_command.h"
#include "harness/commands/reference_command.h"
#include "harness/commands/replay_command.h"
#include "harness/plan/plan.h"
#include "harness/plan/suite_file.h"
#include "harness/run/replicate_farm.h"
#include "harness/session/session.h"
#include "harness/session/shard.h"
#include "harness/verify/block_pyramid.h"
#include "results/context.h"

namespace pcbench {
namespace {

struct RunArguments : ReportArguments {
  std::string suite_path;
  std::vector<std::string> estimators;
  std::vector<std::string> integrands;
  std::vector<std::string> params;  // key=value
  std::uint64_t samples = 0;
  double seconds = 0.0;
  std::uint32_t replicates = 0;
  bool interleave = false;
  bool paired = false;
  bool strategy_images = false;
  bool replicate_images = false;
  bool resume = false;
  std::string shard;  // --shard i/n
  std::string reference_cache = kDefaultReferenceCache;
  std::vector<std::string> require_mdb;  // --require-mdb SCALE=FRACTION, repeatable
  // verify only
  bool verify = false;
  bool exact = false;
  ExternalRequest external;
  ImageSetRequest images;  // --images SET (its --against is external.against)
  // --images and --against as given: each takes several words (the files of an unquoted glob
  // that the shell expanded), joined into one comma-separated list by gather_file_lists.
  std::vector<std::string> image_files, against_files;
  std::string crop;  // --crop X,Y,W,H
};

// `verify -e CONTROL` without an integrand: each negative control on its declared integrand
// and budget, with the honest partners it is compared with (the command line's --param and
// budget flags still apply).
std::vector<ResolvedGrid> declared_grids(const RunArguments& args) {
  const ResolvedGrid controls =
      resolve_names({.estimators = args.estimators, .where = "command line"});
  std::vector<ResolvedGrid> grids;
  for (const EstimatorEntry* control : controls.estimators) {
    if (!control->declared) {
      throw InputError(fmt::format(
          "command line: --integrand is required for '{}' (only a negative control declares its "
          "own integrand)",
          control->name));
    }
    const DeclaredWorkload& workload = *control->declared;
    const ResolvedGrid partners = resolve_names(
        {.estimators = workload.partners,
         .integrands = {workload.integrand},
         .samples = workload.samples,
         .replicates = workload.replicates,
         .where = fmt::format("command line (declared workload of {})", control->name)});
    // The control (resolved above), then its partners.
    ResolvedGrid grid{
        .estimators = {control}, .integrands = partners.integrands, .request = partners.request};
    grid.request.estimators = {control->name};
    for (std::size_t i = 0; i < partners.estimators.size(); ++i) {
      grid.estimators.push_back(partners.estimators[i]);
      grid.request.estimators.push_back(partners.request.estimators[i]);
    }
    grid.request.params = params_from_flags(args.params, grid);
    for (const auto& [key, value] : workload.integrand_params) {
      if (!grid.request.params.count(key)) grid.request.params[key] = {value};
    }
    grids.push_back(std::move(grid));
  }
  return grids;
}

// The one-run form as grids: `--param M=1,4,16` gives three runs.
std::vector<ResolvedGrid> grids_from_flags(const RunArguments& args) {
  if (args.estimators.empty())
    throw InputError("command line: --estimator is required (or give a suite file)");
  if (args.integrands.empty()) {
    if (args.verify) return declared_grids(args);
    throw InputError("command line: --integrand is required (or give a suite file)");
  }
  return {command_line_grid(args.estimators, args.integrands, args.params)};
}

// --images and --against as the one set each names: several words (a glob the shell expanded)
// become a comma-separated list. --against with --estimates takes one file.
void gather_file_lists(RunArguments& args) {
  args.images.images = join_names(args.image_files, ",");
  if (args.against_files.empty()) return;
  if (args.against_files.size() > 1 && args.image_files.empty()) {
    throw InputError(fmt::format(
        "command line: --against takes one file of estimates, not {} ({}); several files are "
        "an image set, which goes with --images",
        args.against_files.size(), join_names(args.against_files, " ")));
  }
  args.external.against = join_names(args.against_files, ",");
}

// `base` with the command line's --require-mdb on top.
ScaleRequirements with_requirements(ScaleRequirements base, const RunArguments& args) {
  for (const std::string& assignment : args.require_mdb) {
    base.set(assignment, "command line: --require-mdb");
  }
  return base;
}

// The session's options from the command line: ReportArguments' and the run's own.
SessionOptions run_session_options(const RunArguments& args, const CommandContext& context) {
  SessionOptions session = session_options(args, context);
  session.escalate = args.verify;
  session.interleave = args.interleave;
  session.reference_cache = args.reference_cache;
  session.strategy_images = args.strategy_images;
  session.replicate_images = args.replicate_images;
  session.scale_requirements = with_requirements(session.scale_requirements, args);
  return session;
}

int run_command(const RunArguments& args, const CommandContext& context) {
  const CLI::App& run_app = context.app;
  if (args.resume && (args.exact || !args.external.estimates.empty())) {
    throw InputError(
        "command line: --resume continues an interrupted run or verify of a suite or selection; "
        "it takes no --exact or --estimates (they are not saved as they go)");
  }
  // Other ranks of an MPI job take no part in verifying files (harness/run/replicate_farm.h).
  if (this_rank() != 0 && (!args.images.images.empty() || !args.external.estimates.empty())) {
    return kExitOk;
  }
  if (!args.images.images.empty()) {
    const bool selection = !args.estimators.empty() || !args.integrands.empty() ||
                           !args.params.empty() || !args.suite_path.empty() || args.exact ||
                           !args.external.estimates.empty() || args.external.reference ||
                           args.external.run_id;
    if (selection || args.resume) {
      throw InputError(
          "command line: --images verifies a set of image files; it takes no suite, --estimator, "
          "--integrand, --param, --exact, --estimates, --reference, --run-id or --resume");
    }
    ImageSetRequest request = args.images;
    request.against = args.external.against;
    if (!args.crop.empty()) request.read.crop = parse_crop(args.crop);
    // Only checked: the input files are read after this, and bad input must leave no folder.
    // The folder is made when the report and images are written (write_file_atomically).
    check_out_dir(args.out_dir, run_app.count("--out") > 0);
    return run_image_set_verification(request, run_session_options(args, context), context.out,
                                      context.err);
  }
  const bool image_options =
      args.images.reference_image || args.images.reference_stderr || args.images.constant ||
      !args.crop.empty() || args.images.read.channels != ImageReadOptions{}.channels ||
      args.images.tile != ImageSetRequest{}.tile || args.images.expect != ImageSetRequest{}.expect;
  if (image_options) {
    throw InputError(
        "command line: --reference-image, --reference-stderr, --constant, --channels, --crop, "
        "--tile and --expect go with --images SET");
  }
  if (!args.external.estimates.empty()) {
    const bool selection = !args.estimators.empty() || !args.integrands.empty() ||
                           !args.params.empty() || !args.suite_path.empty() || args.exact;
    if (selection) {
      throw InputError(
          "command line: --estimates verifies a file of estimates; it takes no suite, "
          "--estimator, --integrand, --param or --exact");
    }
    check_out_dir(args.out_dir, run_app.count("--out") > 0);  // as for --images above
    return run_external_verification(args.external, run_session_options(args, context), context.out,
                                     context.err);
  }
  if (args.resume && run_app.count("--out") == 0) {
    throw InputError(
        "command line: --resume needs --out DIR: the folder of the interrupted session (its "
        "report and checkpoint/)");
  }
  if (args.external.reference || args.external.against || args.external.run_id) {
    throw InputError("command line: --reference, --against and --run-id go with --estimates FILE");
  }
  // --param goes with either: with a suite file it sets the parameter in every row.
  const bool one_run = !args.estimators.empty() || !args.integrands.empty();
  if (one_run && !args.suite_path.empty()) {
    throw InputError("command line: give a suite file or --estimator/--integrand, not both");
  }
  if (!one_run && args.suite_path.empty()) {
    throw InputError("command line: give a suite file or --estimator and --integrand");
  }

  std::vector<ResolvedGrid> grids;
  BudgetDefaults budget;
  SessionOptions session = run_session_options(args, context);
  bool paired = args.paired;
  if (!args.suite_path.empty()) {
    SuiteRequest suite = load_suite(args.suite_path);
    for (GridRequest& grid : suite.grids) {
      ResolvedGrid resolved = resolve_names(std::move(grid));
      // A command-line --param replaces that parameter's values in every row (the full-size
      // form of a CI suite: `-p resolution=128`).
      for (auto& [key, values] : params_from_flags(args.params, resolved)) {
        resolved.request.params[key] = std::move(values);
      }
      grids.push_back(std::move(resolved));
    }
    session.suite_name = suite.name;
    budget.samples = suite.samples;
    if (suite.replicates) budget.replicates = *suite.replicates;
    budget.seconds = suite.seconds;
    if (suite.seed && run_app.count("--seed") == 0) session.seed = *suite.seed;
    session.compare_pairwise = suite.compare_pairwise;
    session.interleave = session.interleave || suite.interleave;
    paired = paired || suite.paired;
    session.strategy_images = session.strategy_images || suite.strategy_images;
    session.scale_requirements = with_requirements(suite.scale_requirements, args);
  } else {
    grids = grids_from_flags(args);
  }
  session.scale_requirements.check_blocks(
      PyramidOptions{}.tile, args.suite_path.empty() ? "command line: --require-mdb"
                                                     : args.suite_path + " or --require-mdb");
  // Options given on the command line override the suite's defaults and its rows.
  if (run_app.count("--samples")) budget.forced_samples = args.samples;
  if (run_app.count("--seconds")) {
    if (run_app.count("--samples")) {
      throw InputError("command line: give --samples or --seconds, not both");
    }
    budget.forced_seconds = args.seconds;
  }
  if (run_app.count("--replicates")) budget.forced_replicates = args.replicates;

  std::optional<Shard> shard;
  if (run_app.count("--shard")) {
    shard = parse_shard(args.shard);
    if (run_app.count("--out") == 0 || args.exact) {
      throw InputError(
          "command line: --shard needs --out DIR (the folder `pcbench merge` reads) and takes no "
          "--exact");
    }
  }
  std::vector<RunPlan> plans = plan_runs(grids, budget);
  if (paired) pair_scene_streams(plans);
  if (this_rank() != 0) {
    // Another rank of an MPI job: only its share of rank 0's runs (--exact runs on rank 0).
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, session.threads);
    return args.exact ? kExitOk : serve_replicates(plans, context.interrupted);
  }
  session.farm = replicate_farm(plans);
  // Checked before anything is written: a journal of another seed or suite is bad input.
  if (args.resume) {
    session.resume =
        std::make_shared<RunStore>(RunStore::resume(args.out_dir, session.seed, plans));
  }
  prepare_out_dir(args.out_dir, run_app.count("--out") > 0);

  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, session.threads);
  if (args.exact) return run_exact_session(plans, session, context.out, context.err);
  if (shard) {
    if (!session.resume) {
      session.resume = std::make_shared<RunStore>(
          RunStore::start(args.out_dir, session.seed, session.suite_name, plans, context.err));
    }
    return run_shard(plans, *shard, session, args.out_dir,
                     shared_arguments({context.argv.begin() + 1, context.argv.end()}), context.out,
                     context.err);
  }
  return run_session(plans, session, context.out, context.err);
}

// The selection and budget options `run` and `verify` share.
void add_run_options(CLI::App* app, RunArguments& args) {
  app->add_option("suite", args.suite_path, "suite file (JSON)");
  app->add_option("--estimator,-e", args.estimators, "estimator(s); a comma list is a grid")
      ->delimiter(',');
  app->add_option("--integrand,-i", args.integrands, "integrand(s); a comma list is a grid")
      ->delimiter(',');
  app->add_option("--param,-p", args.params,
                  "key=value, repeatable; numeric and choice values may be comma lists (a grid)");
  app->add_option("--samples,-n", args.samples,
                  "camera samples per replicate (default 100000 for an analytic integrand, 16 spp "
                  "for a scene, whose samples are per pixel)")
      ->check(CLI::Range(std::uint64_t{1}, kMaxSamples));
  app->add_option("--seconds", args.seconds,
                  "equal time: CPU seconds per replicate; a pilot picks the sample count")
      ->check(CLI::Range(kMinSecondsPerReplicate, kMaxSecondsPerReplicate));
  app->add_option("--replicates,-r", args.replicates, "independent replicates (default 32)")
      ->check(CLI::Range(std::uint32_t{2}, kMaxReplicates));
  add_seed_and_threads_options(app, args.seed, args.threads);
  app->add_option("--out,-o", args.out_dir,
                  "output folder (default results/runs/<date-time>/, linked as results/latest)");
  app->add_flag("--quiet,-q", args.quiet, "no progress and no summary table");
  app->add_flag("--interleave", args.interleave,
                "runs on one integrand take their replicates in turn; prints their efficiency "
                "ratios with intervals");
  app->add_flag("--paired", args.paired,
                "scene runs share their random streams between estimators (the same camera paths "
                "and light pools per replicate) and their block pyramids test the replicate "
                "differences (paired t): more power where the estimators' images correlate");
  app->add_flag("--strategy-images", args.strategy_images,
                "scene runs also write images/<id>_strategies.exr: the mean image of each (s, t) "
                "connection strategy, one layer each, and their shares of the image");
  app->add_flag("--replicate-images", args.replicate_images,
                "scene runs also write each replicate image, images/<id>_rep<k>.exr (k from 0): "
                "what `verify --images` and other tools test");
  app->add_flag(
      "--resume", args.resume,
      "with --out DIR of an interrupted session: restore its finished runs, run the rest");
  app->add_option("--shard", args.shard,
                  "i/n: run share i (0 to n-1) of n of the planned runs into --out DIR's journal, "
                  "no report; `pcbench merge` the n folders for it");
  app->add_option("--require-mdb", args.require_mdb,
                  "SCALE=FRACTION, repeatable: the largest detectable bias a scene comparison must "
                  "reach at a scale of its block pyramid, relative to a bright block's mean; "
                  "SCALE is tile, image or a block edge in pixels (default tile=0.05, "
                  "image=0.01; SCALE=none drops one)")
      ->take_all();
  add_reference_cache_option(app, args.reference_cache);
}

CLI::App* add_run_command(CLI::App& app, RunArguments& args) {
  CLI::App* run = app.add_subcommand("run", "run a suite file, or one estimator on one integrand");
  add_run_options(run, args);
  return run;
}

CLI::App* add_verify_command(CLI::App& app, RunArguments& verify_args) {
  verify_args.verify = true;
  CLI::App* verify = app.add_subcommand(
      "verify",
      "test E[estimate] = reference as one family (a negative control alone runs on its "
      "declared integrand)");
  add_run_options(verify, verify_args);
  verify->add_option("--alpha", verify_args.alpha, "family-wise false-alarm rate (default 0.01)")
      ->check(alpha_check());
  verify->add_flag("--exact", verify_args.exact,
                   "enumerate the resampling step exactly (M <= 6, K <= 3) instead of sampling");
  verify->add_option("--estimates", verify_args.external.estimates,
                     "replicate estimates from any renderer (.csv, .txt, .json or a report)");
  verify->add_option("--run-id", verify_args.external.run_id,
                     "the run to take from a pcbench report given to --estimates");
  verify->add_option("--reference", verify_args.external.reference,
                     "with --estimates: the value to test against, V or V±U (also V+-U)");
  verify
      ->add_option("--against", verify_args.against_files,
                   "with --estimates: a second estimates file, tested two-sample (Welch); with "
                   "--images: a second independent image set, tested block by block (as --images)")
      ->take_all();
  verify
      ->add_option("--images", verify_args.image_files,
                   "replicate images from any renderer (EXR, HDR or PFM), one seed per image: "
                   "files (several, as an unquoted glob expands), a folder, a quoted glob or a "
                   "comma-separated list")
      ->take_all();
  verify->add_option("--reference-image", verify_args.images.reference_image,
                     "with --images: a converged reference image");
  verify->add_option("--reference-stderr", verify_args.images.reference_stderr,
                     "with --reference-image: its per-pixel standard error image");
  verify->add_option("--constant", verify_args.images.constant,
                     "with --images: an exact constant image, V or R,G,B (a furnace)");
  verify
      ->add_option("--channels", verify_args.images.read.channels,
                   "with --images: the three channels to test (default R,G,B)")
      ->delimiter(',')
      ->expected(3);
  verify->add_option("--crop", verify_args.crop, "with --images: the window X,Y,W,H to test");
  verify->add_option("--tile", verify_args.images.tile,
                     "with --images: tile edge in pixels (default 8)");
  verify->add_option("--expect", verify_args.images.expect,
                     "with --images: consistent (default) or biased (a set with a known bias)");
  return verify;
}

int verify_command(const RunArguments& given, const CommandContext& context) {
  RunArguments args = given;
  gather_file_lists(args);
  return run_command(args, context);
}

// A subcommand, and what runs it on the arguments its parsing filled in.
struct Command {
  CLI::App* app;
  std::function<int(const CommandContext&)> run;
};

template <class Arguments>
Command command(CLI::App* app, const Arguments& args,
                int (*run)(const Arguments&, const CommandContext&)) {
  return {app, [&args, run](const CommandContext& context) { return run(args, context); }};
}

// CLI11 would say "A subcommand is required" without naming the subcommands: the message when
// the first argument is neither an option nor a subcommand, or there is none.
std::string subcommand_error(CLI::App& app, const std::vector<std::string>& args) {
  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    commands.push_back(sub->get_name());
  }
  if (!args.empty() && (args[0].rfind('-', 0) == 0 ||
                        std::find(commands.begin(), commands.end(), args[0]) != commands.end())) {
    return "";
  }
  return fmt::format("pcbench: error: {}; valid subcommands: {} (see pcbench --help)\n",
                     args.empty() ? std::string("no subcommand given")
                                  : fmt::format("unknown subcommand '{}'", args[0]),
                     join_names(commands));
}

}  // namespace

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
            const std::atomic<bool>* interrupted) {
  CLI::App app{"pcbench: benchmarks and verifies Monte Carlo light-transport estimators",
               "pcbench"};
  app.set_version_flag("--version", std::string("pcbench ") + pcbench_version());
  app.require_subcommand(1);

  // Each command's arguments, filled in by the parse; the commands in the order of --help.
  ListArguments list;
  RunArguments run;
  RunArguments verify;
  CalibrateArguments calibrate;
  CompareArguments compare;
  ReplayArguments replay;
  ReferenceArguments reference;
  MergeArguments merge;
  PlotArguments plot;
  const std::vector<Command> commands = {
      command(add_list_command(app, list), list, list_command),
      command(add_run_command(app, run), run, run_command),
      command(add_verify_command(app, verify), verify, verify_command),
      command(add_calibrate_command(app, calibrate), calibrate, calibrate_command),
      command(add_compare_command(app, compare), compare, compare_command),
      command(add_replay_command(app, replay), replay, replay_command),
      command(add_reference_command(app, reference), reference, reference_command),
      command(add_merge_command(app, merge), merge, merge_command),
      command(add_plot_command(app, plot), plot, plot_command),
  };

  if (const std::string error = subcommand_error(app, args); !error.empty()) {
    err << error;
    return kExitBadInput;
  }
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);  // CLI11 takes a vector of arguments in reverse order
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e, out, err);
    return code == 0 ? kExitOk : kExitBadInput;
  }

  std::vector<std::string> argv = {"pcbench"};
  argv.insert(argv.end(), args.begin(), args.end());
  for (const Command& parsed : commands) {
    if (!parsed.app->parsed()) continue;
    try {
      return parsed.run(
          {.app = *parsed.app, .argv = argv, .out = out, .err = err, .interrupted = interrupted});
    } catch (const InputError& e) {
      err << "pcbench: error: " << e.what() << "\n";
      return kExitBadInput;
    }
  }
  return kExitBadInput;  // not reached: the parse requires one subcommand
}

}  // namespace pcbench
