#include "harness/commands/compare_command.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <ostream>

#include "harness/session/publish.h"
#include "harness/session/report.h"
#include "harness/verify/report_compare.h"

namespace pcbench {

int run_compare_command(const std::string& report_a, const std::string& report_b,
                        const SessionOptions& options, std::ostream& out, std::ostream& err) {
  const ComparisonOutcome outcome = compare_report_files(report_a, report_b, options.alpha);
  for (const std::string& warning : outcome.warnings)
    err << "pcbench: warning: " << warning << "\n";
  if (!options.quiet) {
    out << fmt::format("{:<16} {:<24} {:<18} {:>9} {:>10} {:>10}  {}\n", "id", "estimator",
                       "integrand", "t", "p_adj", "mdd", "result");
    for (const Comparison& c : outcome.comparisons) {
      out << fmt::format("{:<16} {:<24} {:<18} {:>9.3g} {:>10.3g} {:>10.3g}  {}\n", c.a,
                         c.estimator, c.integrand, c.statistic, c.p_adjusted,
                         c.min_detectable_difference, c.result);
    }
    for (const UncomparedRun& run : outcome.not_compared) {
      out << fmt::format("{:<16} not compared: {}\n", run.id, run.reason);
    }
    if (!outcome.only_in_a.empty()) {
      out << fmt::format("only in {}: {}\n", report_a, fmt::join(outcome.only_in_a, ", "));
    }
    if (!outcome.only_in_b.empty()) {
      out << fmt::format("only in {}: {}\n", report_b, fmt::join(outcome.only_in_b, ", "));
    }
  }
  ReportSections sections;
  sections.comparisons = comparisons_json(outcome.comparisons);
  if (!publish_report(options, sections, out, err)) return kExitRunFailed;
  return outcome.as_expected() ? kExitOk : kExitVerdictDiffers;
}

CLI::App* add_compare_command(CLI::App& app, CompareArguments& args) {
  CLI::App* compare = app.add_subcommand(
      "compare", "two-sample tests between the runs with the same id in two reports");
  compare->add_option("reports", args.reports, "report A and report B")->required()->expected(2);
  compare->add_option("--alpha", args.alpha, "family-wise false-alarm rate (default 0.01)")
      ->check(alpha_check());
  compare->add_option("--out,-o", args.out_dir,
                      "output folder (default results/runs/<date-time>/)");
  compare->add_flag("--quiet,-q", args.quiet, "no table");
  return compare;
}

int compare_command(const CompareArguments& args, const CommandContext& context) {
  prepare_out_dir(args.out_dir, context.app.count("--out") > 0);
  return run_compare_command(args.reports[0], args.reports[1], session_options(args, context),
                             context.out, context.err);
}

}  // namespace pcbench
