#include "harness/commands/run_command.h"

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <ostream>

#include "base/errors.h"
#include "harness/commands/command_line_grid.h"
#include "harness/plan/suite_file.h"
#include "harness/run/replicate_farm.h"
#include "harness/run/run_store.h"
#include "harness/verify/block_pyramid.h"

namespace pcbench {
namespace {

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

// `base` with the command line's --require-mdb on top.
ScaleRequirements with_requirements(ScaleRequirements base, const RunArguments& args) {
  for (const std::string& assignment : args.require_mdb) {
    base.set(assignment, "command line: --require-mdb");
  }
  return base;
}

// What the runs are planned from: grids and the budget's defaults (a suite's, or none), and
// whether scene runs share their streams.
struct PlanInput {
  std::vector<ResolvedGrid> grids;
  BudgetDefaults budget;
  bool paired = false;
};

// The one-run form as grids: `--param M=1,4,16` gives three runs.
PlanInput flag_selection(const RunArguments& args) {
  if (args.estimators.empty())
    throw InputError("command line: --estimator is required (or give a suite file)");
  if (args.integrands.empty()) {
    if (args.verify) return {.grids = declared_grids(args), .budget = {}, .paired = args.paired};
    throw InputError("command line: --integrand is required (or give a suite file)");
  }
  return {.grids = {command_line_grid(args.estimators, args.integrands, args.params)},
          .budget = {},
          .paired = args.paired};
}

// The suite file's grids and defaults, under the command line's options: its session settings
// go into `session`.
PlanInput suite_selection(const RunArguments& args, const CLI::App& app, SessionOptions& session) {
  SuiteRequest suite = load_suite(args.suite_path);
  PlanInput input;
  for (GridRequest& grid : suite.grids) {
    ResolvedGrid resolved = resolve_names(std::move(grid));
    // A command-line --param replaces that parameter's values in every row (the full-size
    // form of a CI suite: `-p resolution=128`).
    for (auto& [key, values] : params_from_flags(args.params, resolved)) {
      resolved.request.params[key] = std::move(values);
    }
    input.grids.push_back(std::move(resolved));
  }
  session.suite_name = suite.name;
  input.budget.samples = suite.samples;
  if (suite.replicates) input.budget.replicates = *suite.replicates;
  input.budget.seconds = suite.seconds;
  if (suite.seed && app.count("--seed") == 0) session.seed = *suite.seed;
  session.compare_pairwise = suite.compare_pairwise;
  session.interleave = session.interleave || suite.interleave;
  input.paired = args.paired || suite.paired;
  session.strategy_images = session.strategy_images || suite.strategy_images;
  session.scale_requirements = with_requirements(suite.scale_requirements, args);
  return input;
}

// Budget options given on the command line override the suite's defaults and its rows.
void force_budget(const RunArguments& args, const CLI::App& app, BudgetDefaults& budget) {
  if (app.count("--samples")) budget.forced_samples = args.samples;
  if (app.count("--seconds")) {
    if (app.count("--samples")) {
      throw InputError("command line: give --samples or --seconds, not both");
    }
    budget.forced_seconds = args.seconds;
  }
  if (app.count("--replicates")) budget.forced_replicates = args.replicates;
}

std::optional<Shard> shard_option(const RunArguments& args, const CLI::App& app) {
  if (app.count("--shard") == 0) return std::nullopt;
  const Shard shard = parse_shard(args.shard);
  if (app.count("--out") == 0 || args.exact) {
    throw InputError(
        "command line: --shard needs --out DIR (the folder `pcbench merge` reads) and takes no "
        "--exact");
  }
  return shard;
}

// A suite file or the command line's estimators and integrands, one of them.
void check_one_selection(const RunArguments& args) {
  // --param goes with either: with a suite file it sets the parameter in every row.
  const bool one_run = !args.estimators.empty() || !args.integrands.empty();
  if (one_run && !args.suite_path.empty()) {
    throw InputError("command line: give a suite file or --estimator/--integrand, not both");
  }
  if (!one_run && args.suite_path.empty()) {
    throw InputError("command line: give a suite file or --estimator and --integrand");
  }
}

int execute(const SessionRun& form, const CommandContext& context) {
  create_out_dir(form.session.out_dir.value_or(""));
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  form.session.threads);
  return run_session(form.plans, form.session, context.out, context.err);
}

int execute(const ExactCheck& form, const CommandContext& context) {
  create_out_dir(form.session.out_dir.value_or(""));
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  form.session.threads);
  return run_exact_session(form.plans, form.session, context.out, context.err);
}

int execute(const ShardRun& form, const CommandContext& context) {
  create_out_dir(form.folder.string());
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  form.session.threads);
  SessionOptions session = form.session;
  if (!session.resume) {
    session.resume = std::make_shared<RunStore>(
        RunStore::start(form.folder, session.seed, session.suite_name, form.plans, context.err));
  }
  return run_shard(form.plans, form.shard, session, form.folder,
                   shared_arguments({context.argv.begin() + 1, context.argv.end()}), context.out,
                   context.err);
}

int execute(const ServeRank& form, const CommandContext& context) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, form.threads);
  return serve_replicates(form.plans, context.interrupted);
}

int execute(const IdleRank& /*form*/, const CommandContext& /*context*/) {
  return kExitOk;
}

}  // namespace

CLI::App* add_run_command(CLI::App& app, RunArguments& args) {
  CLI::App* run = app.add_subcommand("run", "run a suite file, or one estimator on one integrand");
  add_run_options(run, args);
  return run;
}

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
                "differences (paired t): more power where the estimators' images correlate; "
                "with verify --images SET --against SET2: the sets are replicate pairs");
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

void check_resume_has_out(const RunArguments& args, const CLI::App& app) {
  if (args.resume && app.count("--out") == 0) {
    throw InputError(
        "command line: --resume needs --out DIR: the folder of the interrupted session (its "
        "report and checkpoint/)");
  }
}

RunForm plan_run_form(const RunArguments& args, const CommandContext& context) {
  check_one_selection(args);
  SessionOptions session = run_session_options(args, context);
  PlanInput input =
      args.suite_path.empty() ? flag_selection(args) : suite_selection(args, context.app, session);
  session.scale_requirements.check_blocks(
      PyramidOptions{}.tile, args.suite_path.empty() ? "command line: --require-mdb"
                                                     : args.suite_path + " or --require-mdb");
  force_budget(args, context.app, input.budget);
  const std::optional<Shard> shard = shard_option(args, context.app);
  std::vector<RunPlan> plans = plan_runs(input.grids, input.budget);
  if (input.paired) pair_scene_streams(plans);
  if (this_rank() != 0) {
    // Another rank of an MPI job: only its share of rank 0's runs (--exact runs on rank 0).
    if (args.exact) return IdleRank{};
    return ServeRank{.plans = std::move(plans), .threads = session.threads};
  }
  session.farm = replicate_farm(plans);
  // Checked before anything is written: a journal of another seed or suite is bad input.
  if (args.resume) {
    session.resume =
        std::make_shared<RunStore>(RunStore::resume(args.out_dir, session.seed, plans));
  }
  check_out_dir(args.out_dir, context.app.count("--out") > 0);
  if (args.exact) return ExactCheck{.plans = std::move(plans), .session = std::move(session)};
  if (shard) {
    return ShardRun{.plans = std::move(plans),
                    .session = std::move(session),
                    .shard = *shard,
                    .folder = args.out_dir};
  }
  return SessionRun{.plans = std::move(plans), .session = std::move(session)};
}

int run_form(const RunForm& form, const CommandContext& context) {
  return std::visit([&](const auto& one) { return execute(one, context); }, form);
}

int run_command(const RunArguments& args, const CommandContext& context) {
  check_resume_has_out(args, context.app);
  return run_form(plan_run_form(args, context), context);
}

}  // namespace pcbench
