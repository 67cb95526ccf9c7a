// `pcbench plot REPORT.json [--out DIR]`: the report's figures and index.html, made by the
// Python script in results/plot/ with Debian's /usr/bin/python3 (matplotlib, OpenImageIO).
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace pcbench {

// Exit status: 0 written, 2 bad input (no such report, not a report, --out is a file), 3 the
// plotting could not run or failed.
int run_plot_command(const std::string& report, const std::optional<std::string>& out_dir,
                     std::ostream& out, std::ostream& err);

}  // namespace pcbench
