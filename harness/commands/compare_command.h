// `pcbench compare A.json B.json`: "did my change alter this estimator?" Two-sample tests
// between the runs with the same id in two reports (harness/verify/report_compare.h), Holm over the
// pairs, written to a report's comparisons[] and printed.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "harness/commands/command_options.h"
#include "harness/session/session.h"

namespace pcbench {

int run_compare_command(const std::string& report_a, const std::string& report_b,
                        const SessionOptions& options, std::ostream& out, std::ostream& err);

struct CompareArguments : ReportArguments {
  std::vector<std::string> reports;  // A and B
};

// Adds `compare` and its options to `app`.
CLI::App* add_compare_command(CLI::App& app, CompareArguments& args);

// `pcbench compare`.
int compare_command(const CompareArguments& args, const CommandContext& context);

}  // namespace pcbench
