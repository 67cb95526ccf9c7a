#include "harness/session/execution.h"

#include <fmt/format.h>

#include <optional>
#include <ostream>
#include <string>
#include <utility>

#include "harness/run/equal_time.h"
#include "harness/run/interleaved_runs.h"
#include "harness/run/replay.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

// Whether a t-test of the run against its reference can decide: not without a reference
// (pairwise comparisons still can), nor where the integrand declares an infinite variance.
bool t_test_decides(const RunPlan& plan, const Reference& reference) {
  return reference.kind != ReferenceKind::kNone && !plan.integrand->has_tag("infinite-variance");
}

// Student's t assumes a finite variance and replicate means near normal; where the samples say
// otherwise (a heavy tail, a handful of dominant samples), a verdict either way would claim a
// confidence the test does not have, so the run is inconclusive with the reason.
Verdict verdict_for(const RunPlan& plan, const RunResult& result,
                    const SampleDiagnostics& diagnostics) {
  const std::string expect = expected_result(plan, t_test_decides(plan, result.reference));
  if (const std::optional<std::string> reason = untestable_reason(diagnostics)) {
    return untested_verdict(*reason, expect);
  }
  return test_against_reference(result, expect);
}

// What a finished run came to, for the progress log (before the family's correction).
std::string outcome_of(const RunRecord& record) {
  const RunResult& result = record.result;
  if (result.status == RunStatus::kOk && record.verdict) {
    if (!record.verdict->tested) return fmt::format("ok, {}", record.verdict->result);
    return fmt::format("ok, raw p {:.3g}", record.verdict->p_value);
  }
  if (result.error.empty()) return to_string(result.status);
  return fmt::format("{}: {}", to_string(result.status), result.error);
}

// The progress line's name of a run.
std::string run_label(const RunPlan& plan) {
  return fmt::format("{} × {}", plan.estimator->name, plan.integrand->name);
}

// Tests one finished run alone (the family's correction comes later).
RunRecord tested_record(const RunPlan& plan, RunResult result) {
  RunRecord record;
  record.plan = &plan;
  record.result = std::move(result);
  if (record.result.status == RunStatus::kOk) {
    record.aggregates = aggregate(record.result.replicates, record.result.reference, plan.samples);
    record.diagnostics = diagnose_samples(record.result.replicates);
    record.verdict = verdict_for(plan, record.result, record.diagnostics);
  } else if (record.result.status == RunStatus::kInvalid) {
    record.aggregates = aggregate(record.result.replicates, record.result.reference, plan.samples);
  }
  return record;
}

// The command that replays a run's first non-finite sample, as the run ends: a failure's
// diagnosis, so written with --quiet too.
void print_replay(const RunPlan& plan, const RunResult& result, bool quiet,
                  ProgressReporter& progress, std::ostream& err) {
  if (!result.first_nonfinite) return;
  const std::optional<std::string> command = replay_command(plan, *result.first_nonfinite);
  if (!command) return;
  const std::string text = fmt::format(
      "pcbench: {} × {}: first non-finite sample at seed {}, replicate {}, sample {}; replay it "
      "with\n  {}",
      plan.estimator->name, plan.integrand->name, result.first_nonfinite->seed,
      result.first_nonfinite->replicate, result.first_nonfinite->sample, *command);
  if (quiet) {
    err << text << "\n";
  } else {
    progress.message(text);  // not overdrawn by the progress line
  }
}

// A run restored from the journal of the session being resumed, tested alone; null when the
// journal does not hold it. Restored even after Ctrl-C: it costs nothing and the report is
// fuller.
std::optional<RunRecord> restored_record(const RunPlan& plan, const RunServices& services) {
  const SavedRun* saved = services.store.restore(plan.id);
  if (saved == nullptr) return std::nullopt;
  // No work in the progress count: the time left is of the runs still to run.
  services.progress.run_started(run_label(plan), 0);
  RunRecord record = tested_record(plan, saved->result);
  services.progress.run_finished("restored from " + services.store.file_of(plan.id).string());
  return record;
}

// A run that has just finished: saved to the journal (so that --resume can restore it), its
// replay command printed where it had a non-finite sample, tested alone.
RunRecord finished_record(const RunPlan& plan, RunResult result, const RunServices& services) {
  services.store.save(plan, result, services.err);
  print_replay(plan, result, services.options.quiet, services.progress, services.err);
  return tested_record(plan, std::move(result));
}

// The runs the journal does not hold, interleaved (their replicates in turn), then each saved and
// tested in the plans' order among the restored ones.
ExecutedRuns execute_interleaved_runs(const std::vector<const RunPlan*>& plans,
                                      const std::vector<const RunPlan*>& pending,
                                      const RunServices& services) {
  ExecutedRuns runs;
  runs.records.reserve(plans.size());
  std::vector<RunResult> results = execute_interleaved(pending, services.runner, services.progress);
  std::size_t next = 0;
  for (const RunPlan* plan : plans) {
    if (std::optional<RunRecord> restored = restored_record(*plan, services)) {
      runs.records.push_back(std::move(*restored));
      continue;
    }
    runs.records.push_back(finished_record(*plan, std::move(results[next++]), services));
    if (runs.records.back().result.status == RunStatus::kNotRun) runs.interrupted = true;
  }
  return runs;
}

// One run after another; under MPI the farm is told the pending runs first, so that the other
// ranks start on their share of all of them at once.
ExecutedRuns execute_in_turn(const std::vector<const RunPlan*>& plans,
                             const std::vector<const RunPlan*>& pending,
                             const RunServices& services) {
  ExecutedRuns runs;
  runs.records.reserve(plans.size());
  if (services.options.farm != nullptr) services.options.farm->announce(pending, services.runner);
  for (const RunPlan* plan : plans) {
    runs.records.push_back(execute_and_test(*plan, runs.interrupted, services));
  }
  return runs;
}

}  // namespace

std::uint64_t work_to_do(const std::vector<RunPlan>& plans, const RunStore& store) {
  std::uint64_t work = 0;
  for (const RunPlan& plan : plans) {
    if (store.find(plan.id) == nullptr) work += plan.total_samples();
  }
  return work;
}

std::vector<const RunPlan*> choose_budgets(const std::vector<RunPlan>& plans,
                                           std::deque<RunPlan>& chosen,
                                           const RunServices& services) {
  const SessionOptions& options = services.options;
  std::vector<const RunPlan*> to_run;
  for (const RunPlan& plan : plans) {
    to_run.push_back(&plan);
    if (!plan.seconds) continue;
    if (const SavedRun* saved = services.store.find(plan.id)) {
      chosen.push_back(restored_choice(plan, *saved));
      to_run.back() = &chosen.back();
    } else if (!(options.interrupted != nullptr && options.interrupted->load())) {
      chosen.push_back(choose_samples(plan, services.runner, services.progress));
      to_run.back() = &chosen.back();
      // The pilot's choice replaces the planned count in the time left.
      services.progress.add_work(chosen.back().total_samples() - plan.total_samples(), 0);
    }
  }
  return to_run;
}

ExecutedRuns execute_runs(const std::vector<const RunPlan*>& plans, const RunServices& services) {
  // The journal's runs are restored; the others run.
  std::vector<const RunPlan*> pending;
  for (const RunPlan* plan : plans) {
    if (services.store.find(plan->id) == nullptr) pending.push_back(plan);
  }
  return services.options.interleave ? execute_interleaved_runs(plans, pending, services)
                                     : execute_in_turn(plans, pending, services);
}

RunRecord execute_and_test(const RunPlan& plan, bool& interrupted, const RunServices& services) {
  if (std::optional<RunRecord> restored = restored_record(plan, services)) {
    return std::move(*restored);
  }
  const SessionOptions& options = services.options;
  if (options.interrupted != nullptr && options.interrupted->load()) interrupted = true;
  if (interrupted) {
    return tested_record(plan, not_run_result(plan, "interrupted before the run started"));
  }
  // The session's options with this run's progress counter.
  RunnerOptions this_run = services.runner;
  this_run.samples_done = services.progress.run_started(run_label(plan), plan.total_samples());
  RunResult result =
      options.farm != nullptr ? options.farm->run(plan, this_run) : execute_run(plan, this_run);
  if (result.status == RunStatus::kNotRun) interrupted = true;
  RunRecord record = finished_record(plan, std::move(result), services);
  services.progress.run_finished(outcome_of(record));
  return record;
}

}  // namespace pcbench
