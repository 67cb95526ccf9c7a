// Publishing a session's report: the one way every command that writes report.json does it
// (run, verify and its --exact, --estimates and --images forms, --resume, merge, compare,
// calibrate), so that each report is written atomically, linked as results/latest when it went
// to the default folder, and announced on stdout alike.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <vector>

#include "harness/session/report.h"
#include "harness/session/session.h"
#include "harness/verify/run_record.h"
#include "results/context.h"

namespace pcbench {

// The folder a session's report (and images) go to: options.out_dir, or a new
// results/runs/<UTC date-time>/ (never an existing one).
std::filesystem::path report_folder(const SessionOptions& options);

// The report's context of a session: the build, options.argv, options.seed and options.threads.
Context session_context(const SessionOptions& options);

// Writes the report (results/report.schema.json) of `runs` and `sections` under
// options.suite_name as `folder`/report.json, atomically (base/atomic_file.h); points
// results/latest at `folder` when options.out_dir is unset (the default folder); says
// "report: PATH" on `out`. Returns false, after writing why to `err`, when the report could not
// be written (a failed link is only a warning).
bool publish_report(const SessionOptions& options, const std::filesystem::path& folder,
                    const Context& context, const std::vector<RunRecord>& runs,
                    const ReportSections& sections, std::ostream& out, std::ostream& err);

// A report without runs (checks, comparisons, calibrations) into report_folder(options), with
// session_context(options).
bool publish_report(const SessionOptions& options, const ReportSections& sections,
                    std::ostream& out, std::ostream& err);

}  // namespace pcbench
