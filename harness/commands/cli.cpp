#include "harness/commands/cli.h"

#include <fmt/format.h>

// GCC 12 sees a possible null dereference in CLI11's Option::results<std::vector<std::string>>
// (std::vector::emplace_back inlined into it), a false positive of -Wnull-dereference at -O3 in
// a system header.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <CLI/CLI.hpp>
#pragma GCC diagnostic pop
#include <algorithm>
#include <functional>
#include <ostream>

#include "base/comma_list.h"
#include "base/errors.h"
#include "harness/commands/calibrate_command.h"
#include "harness/commands/command_options.h"
#include "harness/commands/compare_command.h"
#include "harness/commands/export_command.h"
#include "harness/commands/list_command.h"
#include "harness/commands/merge_command.h"
#include "harness/commands/plot_command.h"
#include "harness/commands/reference_command.h"
#include "harness/commands/replay_command.h"
#include "harness/commands/run_command.h"
#include "harness/commands/verify_command.h"
#include "harness/session/session.h"
#include "results/context.h"

namespace pcbench {
namespace {

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
std::string subcommand_error(const CLI::App& app, const std::vector<std::string>& args) {
  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
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
  VerifyArguments verify;
  CalibrateArguments calibrate;
  CompareArguments compare;
  ReplayArguments replay;
  ReferenceArguments reference;
  MergeArguments merge;
  PlotArguments plot;
  ExportArguments export_args;
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
      command(add_export_command(app, export_args), export_args, export_command),
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
