// `pcbench plot REPORT.json [--out DIR]`: the report's figures and index.html, made by the
// Python script in results/plot/ with Debian's /usr/bin/python3 (matplotlib, OpenImageIO).
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

#include "harness/commands/command_options.h"

namespace pcbench {

// Exit status: 0 written, 2 bad input (no such report, not a report, --out is a file), 3 the
// plotting could not run or failed.
int run_plot_command(const std::string& report, const std::optional<std::string>& out_dir,
                     std::ostream& out, std::ostream& err);

struct PlotArguments {
  std::string report;
  std::optional<std::string> out_dir;
};

// Adds `plot` and its options to `app`.
CLI::App* add_plot_command(CLI::App& app, PlotArguments& args);

// `pcbench plot`.
int plot_command(const PlotArguments& args, const CommandContext& context);

}  // namespace pcbench
