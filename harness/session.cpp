#include "harness/session.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include <unistd.h>

#include "harness/statistics.h"
#include "harness/summary.h"
#include "results/report.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

// results/runs/<UTC date-time>[-k]: a new folder name, never an existing one.
fs::path default_run_folder() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::array<char, 32> stamp{};
  std::strftime(stamp.data(), stamp.size(), "%Y%m%d-%H%M%S", &tm);
  const fs::path runs = fs::path("results") / "runs";
  fs::path folder = runs / stamp.data();
  for (int k = 2; fs::exists(folder); ++k) folder = runs / fmt::format("{}-{}", stamp.data(), k);
  return folder;
}

// Points results/latest at `folder`, replacing the old link atomically.
void update_latest_link(const fs::path& folder) {
  const fs::path link = fs::path("results") / "latest";
  const fs::path temporary = fs::path("results") / fmt::format(".latest.{}", ::getpid());
  std::error_code ignored;
  fs::remove(temporary, ignored);
  fs::create_directory_symlink(fs::relative(folder, "results"), temporary);
  std::error_code error;
  fs::rename(temporary, link, error);
  if (error) {
    fs::remove(temporary, ignored);
    throw std::runtime_error(link.string() + ": " + error.message());
  }
}

bool declared_infinite_variance(const RunPlan& plan) {
  return plan.integrand->has_tag("infinite-variance");
}

std::string default_expectation(const RunPlan& plan, const Reference& reference) {
  if (plan.expect) return *plan.expect;
  if (plan.estimator->biased) return "biased";
  if (declared_infinite_variance(plan)) return "inconclusive";
  return reference.kind == ReferenceKind::kNone ? "inconclusive" : "consistent";
}

// Student's t assumes a finite variance and replicate means near normal; where the samples say
// otherwise (a heavy tail, a handful of dominant samples), a verdict either way would claim a
// confidence the test does not have, so the run is inconclusive with the reason.
Verdict verdict_for(const RunPlan& plan, const RunResult& result,
                    const SampleDiagnostics& diagnostics) {
  const std::string expect = default_expectation(plan, result.reference);
  if (const std::optional<std::string> reason = untestable_reason(diagnostics)) {
    return untested_verdict(*reason, expect);
  }
  return test_against_reference(result.replicates, result.reference, expect);
}

}  // namespace

std::optional<fs::path> publish_report(const std::string& report, const SessionOptions& options,
                                       std::ostream& err) {
  const bool default_folder = !options.out_dir.has_value();
  const fs::path folder = default_folder ? default_run_folder() : fs::path(*options.out_dir);
  const fs::path report_path = folder / "report.json";
  try {
    write_file_atomically(report_path, report);
  } catch (const std::exception& e) {
    err << "pcbench: error: cannot write the report " << report_path.string() << ": " << e.what()
        << "\n";
    return std::nullopt;
  }
  if (default_folder) {
    try {
      update_latest_link(folder);
    } catch (const std::exception& e) {
      // The report is written; only the convenience link failed.
      err << "pcbench: warning: results/latest not updated: " << e.what() << "\n";
    }
  }
  return report_path;
}

int run_exact_session(const std::vector<RunPlan>& plans, const SessionOptions& options,
                      std::ostream& out, std::ostream& err) {
  ReportSections sections;
  bool differs = false;
  for (const RunPlan& plan : plans) {
    ExactRecord record{.plan = &plan, .check = exact_check(plan, options.seed)};
    record.expect = plan.expect               ? *plan.expect
                    : plan.estimator->biased  ? "biased"
                    : record.check.applicable ? "consistent"
                                              : "inconclusive";
    if (record.check.result != record.expect) differs = true;
    if (!options.quiet) {
      out << fmt::format("{:<24} {:<18} {:<12} (expected {}): {}\n", plan.estimator->name,
                         plan.integrand->name, record.check.result, record.expect,
                         record.check.reason);
    }
    sections.exact_checks.push_back(std::move(record));
  }
  const std::optional<fs::path> report_path =
      publish_report(report_json(gather_context(options.argv, options.seed, options.threads),
                                 options.suite_name, {}, sections),
                     options, err);
  if (!report_path) return kExitRunFailed;
  out << "report: " << report_path->string() << "\n";
  return differs ? kExitVerdictDiffers : kExitOk;
}

int run_session(const std::vector<RunPlan>& plans, const SessionOptions& options, std::ostream& out,
                std::ostream& err) {
  std::vector<RunRecord> records;
  records.reserve(plans.size());
  bool interrupted = false;
  for (const RunPlan& plan : plans) {
    RunRecord record;
    record.plan = &plan;
    if (options.interrupted != nullptr && options.interrupted->load()) interrupted = true;
    if (interrupted) {
      record.result.status = RunStatus::kNotRun;
      record.result.reference = plan.made_integrand->reference();
      record.result.error = "interrupted before the run started";
    } else {
      if (!options.quiet) {
        err << fmt::format("running {} × {} ({} samples × {} replicates)\n", plan.estimator->name,
                           plan.integrand->name, plan.samples, plan.replicates);
      }
      record.result = execute_run(plan, {.seed = options.seed, .interrupted = options.interrupted});
      if (record.result.status == RunStatus::kNotRun) interrupted = true;
    }
    if (record.result.status == RunStatus::kOk) {
      record.aggregates =
          aggregate(record.result.replicates, record.result.reference, plan.samples);
      record.diagnostics = diagnose_samples(record.result.replicates);
      record.verdict = verdict_for(plan, record.result, record.diagnostics);
    } else if (record.result.status == RunStatus::kInvalid) {
      record.aggregates =
          aggregate(record.result.replicates, record.result.reference, plan.samples);
    }
    records.push_back(std::move(record));
  }

  std::vector<Verdict*> family;
  for (RunRecord& record : records) family.push_back(record.verdict ? &*record.verdict : nullptr);
  decide_family(family, options.alpha);

  const std::optional<fs::path> report_path =
      publish_report(report_json(gather_context(options.argv, options.seed, options.threads),
                                 options.suite_name, records),
                     options, err);
  if (!options.quiet) print_summary(records, out);
  if (!report_path) return kExitRunFailed;
  out << "report: " << report_path->string() << "\n";

  bool differs = false;
  bool failed = false;
  for (const RunRecord& record : records) {
    if (record.verdict && record.verdict->result != record.verdict->expect) differs = true;
    if (record.result.status == RunStatus::kError || record.result.status == RunStatus::kInvalid) {
      failed = true;
    }
  }
  if (interrupted) return kExitInterrupted;
  if (differs) return kExitVerdictDiffers;
  if (failed) return kExitRunFailed;
  return kExitOk;
}

}  // namespace pcbench
