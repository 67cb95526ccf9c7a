#include "harness/commands/plot_command.h"

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <vector>

#include "base/child_process.h"
#include "harness/session/session.h"

namespace pcbench {

namespace {

// The script and the interpreter, each overridable from the environment: PCBENCH_PLOT_SCRIPT
// for an installed copy, PCBENCH_PYTHON for another Python with matplotlib. Debian's
// /usr/bin/python3 is the default because a python3 earlier on PATH may not see Debian's
// matplotlib (DEPENDENCIES.md).
std::string from_environment(const char* name, const char* fallback) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? value : fallback;
}

}  // namespace

int run_plot_command(const std::string& report, const std::optional<std::string>& out_dir,
                     std::ostream& out, std::ostream& err) {
  const std::string script = from_environment("PCBENCH_PLOT_SCRIPT", PCBENCH_PLOT_SCRIPT);
  const std::string python = from_environment("PCBENCH_PYTHON", "/usr/bin/python3");
  if (!std::filesystem::is_regular_file(report)) {
    err << "pcbench: error: plot: " << report << ": no such report file\n";
    return kExitBadInput;
  }
  for (const auto& [what, path] : {std::pair{"plotting script", script}, {"Python", python}}) {
    if (!std::filesystem::exists(path)) {
      err << "pcbench: error: plot: the " << what << " " << path
          << " is missing (bash scripts/install-deps.sh installs Python and matplotlib; "
             "PCBENCH_PLOT_SCRIPT and PCBENCH_PYTHON override the paths)\n";
      return kExitRunFailed;
    }
  }
  std::vector<std::string> argv = {python, script, report};
  if (out_dir) argv.insert(argv.end(), {"--out", *out_dir});
  const int status = run_child_process(argv, out, err);
  if (status == kExitOk || status == kExitBadInput) return status;
  return kExitRunFailed;
}

CLI::App* add_plot_command(CLI::App& app, PlotArguments& args) {
  CLI::App* plot = app.add_subcommand(
      "plot", "figures of a report and an HTML page (index.html) with them and its runs");
  plot->add_option("report", args.report, "a report.json written by pcbench")->required();
  plot->add_option("--out,-o", args.out_dir, "folder for the figures (default: plots/ beside it)");
  return plot;
}

int plot_command(const PlotArguments& args, const CommandContext& context) {
  return run_plot_command(args.report, args.out_dir, context.out, context.err);
}

}  // namespace pcbench
