#include "harness/session/session.h"

#include <fmt/format.h>

#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <utility>

#include "harness/run/progress.h"
#include "harness/session/execution.h"
#include "harness/session/family_test.h"
#include "harness/session/publish.h"
#include "harness/session/report.h"
#include "harness/session/summary.h"
#include "harness/verify/block_verdicts.h"
#include "harness/verify/efficiency_ratio.h"
#include "harness/verify/report_compare.h"
#include "harness/verify/scene_verification.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

// The journal that saves each finished run in `folder` as it finishes (harness/run/run_store.h):
// the resumed session's, or a new one. Null, after saying why on `err`, when the folder cannot
// be written.
std::shared_ptr<RunStore> open_journal(const fs::path& folder, const std::vector<RunPlan>& plans,
                                       const SessionOptions& options, std::ostream& err) {
  if (options.resume) return options.resume;
  try {
    return std::make_shared<RunStore>(
        RunStore::start(folder, options.seed, options.suite_name, plans, err));
  } catch (const std::exception& e) {
    err << "pcbench: error: cannot write to " << folder.string() << ": " << e.what() << "\n";
    return nullptr;
  }
}

// The comparisons as the report and the summary state them, each with its verdict's figures.
std::vector<Comparison> finished_comparisons(std::vector<std::pair<Comparison, Verdict>> tested) {
  std::vector<Comparison> finished;
  for (auto& [comparison, verdict] : tested) {
    finish_comparison(comparison, verdict);
    finished.push_back(std::move(comparison));
  }
  return finished;
}

// The summary on `out`: the table of runs, each comparison, the scene pyramids' power and, for
// interleaved runs, their efficiency ratios.
void print_session_summary(const std::vector<RunRecord>& records,
                           const std::vector<Comparison>& comparisons,
                           const nlohmann::json& efficiency_ratios, bool interleaved,
                           std::ostream& out) {
  print_summary(records, out);
  for (const Comparison& c : comparisons) {
    out << fmt::format("  compared {} on {}: {}{} ({})\n", c.estimator, c.integrand, c.result,
                       c.result == c.expect ? "" : fmt::format(" (expected {})", c.expect),
                       c.reason);
  }
  for (const std::string& line : scene_power_lines(comparisons)) out << "  " << line << "\n";
  if (interleaved) print_efficiency_ratios(efficiency_ratios, out);
}

// The scene images (which fill the records' image sections) and the report, in `folder`. False,
// after saying why on `err`, when either could not be written.
bool write_report(const fs::path& folder, const RunStore& store, std::vector<RunRecord>& records,
                  const ReportSections& sections, const SessionOptions& options, std::ostream& out,
                  std::ostream& err) {
  try {
    const ReferenceCache cache(options.reference_cache);
    write_scene_images(records, folder, &cache, options.replicate_images, err);
    Context context = session_context(options);
    if (options.resume) context.restored_runs = store.restored();
    if (options.farm != nullptr) context.ranks = rank_count();
    return publish_report(options, folder, context, records, sections, out, err);
  } catch (const std::exception& e) {
    err << "pcbench: error: cannot write the images of " << folder.string() << ": " << e.what()
        << "\n";
    return false;
  }
}

// Publish: the summary (unless quiet), then the images and the report; the journal is then
// discarded (the report holds every run), or, after Ctrl-C, kept with the command that runs the
// rest. False when the report could not be written.
bool publish_session(const fs::path& folder, RunStore& store, ExecutedRuns& runs,
                     const std::vector<Comparison>& comparisons, const SessionOptions& options,
                     std::ostream& out, std::ostream& err) {
  ReportSections sections;
  sections.comparisons = comparisons_json(comparisons);
  sections.efficiency_ratios = efficiency_ratios_json(runs.records, options.interleave);
  if (!options.quiet) {
    print_session_summary(runs.records, comparisons, sections.efficiency_ratios, options.interleave,
                          out);
  }
  if (!write_report(folder, store, runs.records, sections, options, out, err)) return false;
  if (runs.interrupted) {
    err << fmt::format(
        "pcbench: interrupted; the finished runs are saved in {}: the same command with --out {} "
        "--resume runs the rest\n",
        store.directory().string(), folder.string());
  } else {
    store.discard(err);
  }
  return true;
}

// The exit status of a published session: interrupted, else a verdict other than expected, else
// a run that failed (error or invalid), else ok.
int exit_status(const ExecutedRuns& runs, const std::vector<Comparison>& comparisons) {
  bool differs = false;
  bool failed = false;
  for (const RunRecord& record : runs.records) {
    if (record.verdict && record.verdict->result != record.verdict->expect) differs = true;
    if (record.result.status == RunStatus::kError || record.result.status == RunStatus::kInvalid) {
      failed = true;
    }
  }
  for (const Comparison& c : comparisons) {
    if (c.result != c.expect) differs = true;
  }
  if (runs.interrupted) return kExitInterrupted;
  if (differs) return kExitVerdictDiffers;
  if (failed) return kExitRunFailed;
  return kExitOk;
}

}  // namespace

int run_exact_session(const std::vector<RunPlan>& plans, const SessionOptions& options,
                      std::ostream& out, std::ostream& err) {
  ReportSections sections;
  bool differs = false;
  for (const RunPlan& plan : plans) {
    ExactRecord record{.plan = &plan, .check = exact_check(plan, options.seed)};
    record.expect = expected_result(plan, record.check.applicable);
    if (record.check.result != record.expect) differs = true;
    if (!options.quiet) {
      out << fmt::format("{:<24} {:<18} {:<12} (expected {}): {}\n", plan.estimator->name,
                         plan.integrand->name, record.check.result, record.expect,
                         record.check.reason);
    }
    sections.exact_checks.push_back(std::move(record));
  }
  if (!publish_report(options, sections, out, err)) return kExitRunFailed;
  return differs ? kExitVerdictDiffers : kExitOk;
}

RunnerOptions runner_options(const SessionOptions& options) {
  return {.seed = options.seed,
          .interrupted = options.interrupted,
          .strategy_images = options.strategy_images};
}

// The steps in order: choose budgets (pilots), execute, test the family, escalate, publish.
// The journal and the progress line serve every step that runs; the plans made on the way live
// until the report is written, since the records point at them.
int run_session(const std::vector<RunPlan>& plans, const SessionOptions& options, std::ostream& out,
                std::ostream& err) {
  const fs::path folder = report_folder(options);  // first: runs are saved there as they finish
  const std::shared_ptr<RunStore> store = open_journal(folder, plans, options, err);
  if (!store) return kExitRunFailed;
  const RunnerOptions runner = runner_options(options);
  std::optional<ProgressReporter> progress;
  progress.emplace(progress_mode(err, options.quiet), err, plans.size(), work_to_do(plans, *store));
  const RunServices services{options, runner, *store, *progress, err};
  std::deque<RunPlan> made_plans;  // pilots' choices and later stages
  ExecutedRuns runs = execute_runs(choose_budgets(plans, made_plans, services), services);
  if (options.journal_only) return runs.interrupted ? kExitInterrupted : kExitOk;
  std::vector<std::pair<Comparison, Verdict>> family = test_family(runs.records, options);
  if (options.escalate) escalate(runs, made_plans, services);
  progress.reset();  // clears the terminal line before the summary
  const std::vector<Comparison> comparisons = finished_comparisons(std::move(family));
  if (!publish_session(folder, *store, runs, comparisons, options, out, err)) return kExitRunFailed;
  return exit_status(runs, comparisons);
}

}  // namespace pcbench
