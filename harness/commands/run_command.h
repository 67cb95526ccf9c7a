// `pcbench run`: a suite file, or an -e/-i selection, planned and run; `verify` on a suite or
// selection (harness/commands/verify_command.h) goes the same way with its tests added. Each form
// a planned session takes is a type of its own (RunForm), parsed and checked once from the
// arguments (plan_run_form), then run by its own function (run_form).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "harness/commands/command_options.h"
#include "harness/plan/plan.h"
#include "harness/session/session.h"
#include "harness/session/shard.h"
#include "harness/verify/reference_cache.h"

namespace pcbench {

// The arguments of `run`, and of `verify` on a suite or selection.
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
  bool verify = false;                   // `verify`: escalation, a negative control's workload
  bool exact = false;                    // verify --exact
};

// Adds `run` and its options to `app`.
CLI::App* add_run_command(CLI::App& app, RunArguments& args);

// The selection and budget options `run` and `verify` share.
void add_run_options(CLI::App* app, RunArguments& args);

// The session's options from the command line: ReportArguments' and the run's own.
SessionOptions run_session_options(const RunArguments& args, const CommandContext& context);

// The forms a planned suite or selection runs in.
// A session: runs, tests, reports (with --resume, of the interrupted session's journal).
struct SessionRun {
  std::vector<RunPlan> plans;
  SessionOptions session;
};
// verify --exact: the resampling step enumerated exactly.
struct ExactCheck {
  std::vector<RunPlan> plans;
  SessionOptions session;
};
// --shard i/n: the share's runs into the folder's journal, no report.
struct ShardRun {
  std::vector<RunPlan> plans;
  SessionOptions session;
  Shard shard;
  std::filesystem::path folder;
};
// Another rank of an MPI job: its share of rank 0's runs.
struct ServeRank {
  std::vector<RunPlan> plans;
  unsigned threads = 0;
};
// Another rank of an MPI job with no share (--exact and files run on rank 0).
struct IdleRank {};
using RunForm = std::variant<SessionRun, ExactCheck, ShardRun, ServeRank, IdleRank>;

// --resume needs --out DIR. (verify checks it before its own refusals, then plans.)
void check_resume_has_out(const RunArguments& args, const CLI::App& app);

// The suite or selection, planned, as the form it runs in. Throws InputError on bad input,
// before anything is written.
RunForm plan_run_form(const RunArguments& args, const CommandContext& context);

// Runs the form; returns the exit status.
int run_form(const RunForm& form, const CommandContext& context);

// `pcbench run`.
int run_command(const RunArguments& args, const CommandContext& context);

}  // namespace pcbench
