#include "harness/session/session.h"

#include "harness/verify/scene_verification.h"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include "harness/run/equal_time.h"
#include "harness/run/interleaved_runs.h"
#include "harness/run/progress.h"
#include "harness/run/replay.h"
#include "harness/session/publish.h"
#include "harness/session/report.h"
#include "harness/session/summary.h"
#include "harness/verify/block_verdicts.h"
#include "harness/verify/efficiency_ratio.h"
#include "harness/verify/report_compare.h"
#include "harness/verify/rounding_bound.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

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

namespace {

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
std::optional<RunRecord> restored_record(const RunPlan& plan, RunStore& store,
                                         ProgressReporter& progress) {
  const SavedRun* saved = store.restore(plan.id);
  if (saved == nullptr) return std::nullopt;
  // No work in the progress count: the time left is of the runs still to run.
  progress.run_started(fmt::format("{} × {}", plan.estimator->name, plan.integrand->name), 0);
  RunRecord record = tested_record(plan, saved->result);
  progress.run_finished("restored from " + store.file_of(plan.id).string());
  return record;
}

// A run that has just finished: saved to the journal (so that --resume can restore it), its
// replay command printed where it had a non-finite sample, tested alone.
RunRecord finished_record(const RunPlan& plan, RunResult result, const SessionOptions& options,
                          RunStore& store, ProgressReporter& progress, std::ostream& err) {
  store.save(plan, result, err);
  print_replay(plan, result, options.quiet, progress, err);
  return tested_record(plan, std::move(result));
}

// Runs one plan, or restores it from the journal, and tests it alone.
RunRecord execute_and_test(const RunPlan& plan, const SessionOptions& options,
                           const RunnerOptions& runner, RunStore& store, bool& interrupted,
                           ProgressReporter& progress, std::ostream& err) {
  if (std::optional<RunRecord> restored = restored_record(plan, store, progress)) {
    return std::move(*restored);
  }
  if (options.interrupted != nullptr && options.interrupted->load()) interrupted = true;
  if (interrupted) {
    return tested_record(plan, not_run_result(plan, "interrupted before the run started"));
  }
  // The session's options with this run's progress counter.
  RunnerOptions this_run = runner;
  this_run.samples_done = progress.run_started(
      fmt::format("{} × {}", plan.estimator->name, plan.integrand->name), plan.total_samples());
  RunResult result =
      options.farm != nullptr ? options.farm->run(plan, this_run) : execute_run(plan, this_run);
  if (result.status == RunStatus::kNotRun) interrupted = true;
  RunRecord record = finished_record(plan, std::move(result), options, store, progress, err);
  progress.run_finished(outcome_of(record));
  return record;
}

// Worth more samples: a test that was not rejected but came close, or a run that had too few
// effective samples to be tested (a heavy tail stays heavy with more samples: not escalated).
bool wants_escalation(const RunRecord& record) {
  if (!record.verdict || record.plan->samples * kEscalationFactor > kMaxSamples) return false;
  const Verdict& v = *record.verdict;
  if (v.tested) {
    return v.result == "consistent" && v.p_adjusted <= kBorderlineFactor * v.alpha;
  }
  return record.result.reference.kind != ReferenceKind::kNone &&
         record.diagnostics.min_effective_samples < kMinEffectiveSamples;
}

// Whether a finished run's replicates can enter a two-sample test (the same guards as a test
// against a reference: no heavy tail, enough effective samples).
bool comparable(const RunRecord& record) {
  return record.verdict && !untestable_reason(record.diagnostics).has_value();
}

// Two-sample Welch tests between pairs of finished runs on the same integrand with the same
// integrand parameters: every pair (`all_pairs`, the suite's "compare": "pairwise"), or only
// pairs on integrands without a reference, where they are the only test there is (verify). Two
// honest estimators are expected not to differ, an honest one and a negative control to differ;
// two controls are not compared.
std::vector<std::pair<Comparison, Verdict>> pairwise_comparisons(
    const std::vector<RunRecord>& records, bool all_pairs) {
  std::vector<std::pair<Comparison, Verdict>> out;
  for (std::size_t i = 0; i < records.size(); ++i) {
    for (std::size_t j = i + 1; j < records.size(); ++j) {
      const RunRecord& a = records[i];
      const RunRecord& b = records[j];
      if (!comparable(a) || !comparable(b) || a.plan->integrand != b.plan->integrand ||
          a.plan->integrand_params.values() != b.plan->integrand_params.values()) {
        continue;
      }
      if (!all_pairs && a.result.reference.kind != ReferenceKind::kNone) continue;
      // Scenes are compared block by block instead (scene_block_comparisons).
      if (a.plan->render) continue;
      const int biased = a.plan->estimator->biased + b.plan->estimator->biased;
      if (biased == 2) continue;
      std::vector<double> xa, xb;
      for (const ReplicateResult& r : a.result.replicates) xa.push_back(r.estimate);
      for (const ReplicateResult& r : b.result.replicates) xb.push_back(r.estimate);
      // Each mean's rounding bound (rounding_bound.h): two runs of a constant integrand may
      // differ by an ulp with no spread at all.
      const TwoSampleTest test = with_rounding_floor(
          welch_two_sample(xa, xb),
          rounding_bound(a.result.replicates, sample_roundings(a.result.counters)) +
              rounding_bound(b.result.replicates, sample_roundings(b.result.counters)));
      Comparison c = comparison_from(test, a.plan->id, b.plan->id, xa.size(), xb.size());
      c.estimator = a.plan->estimator->name + " vs " + b.plan->estimator->name;
      c.integrand = a.plan->integrand->name;
      c.expect = biased == 1 ? "biased" : "consistent";
      Verdict verdict = two_sample_verdict(test, c.expect);
      out.emplace_back(std::move(c), std::move(verdict));
    }
  }
  return out;
}

}  // namespace

RunnerOptions runner_options(const SessionOptions& options) {
  return {.seed = options.seed,
          .interrupted = options.interrupted,
          .strategy_images = options.strategy_images};
}

int run_session(const std::vector<RunPlan>& plans, const SessionOptions& options, std::ostream& out,
                std::ostream& err) {
  // The folder is chosen first: finished runs are saved there as they finish
  // (harness/run/run_store.h).
  const fs::path folder = report_folder(options);
  std::shared_ptr<RunStore> store = options.resume;
  if (!store) {
    try {
      store = std::make_shared<RunStore>(
          RunStore::start(folder, options.seed, options.suite_name, plans, err));
    } catch (const std::exception& e) {
      err << "pcbench: error: cannot write to " << folder.string() << ": " << e.what() << "\n";
      return kExitRunFailed;
    }
  }

  const RunnerOptions runner = runner_options(options);
  std::vector<RunRecord> records;
  records.reserve(plans.size());
  bool interrupted = false;
  std::deque<RunPlan> chosen_plans;  // stable addresses for the records that point at them
  std::uint64_t planned_work = 0;
  for (const RunPlan& plan : plans) {
    if (store->find(plan.id) == nullptr) planned_work += plan.total_samples();
  }
  std::optional<ProgressReporter> progress;
  progress.emplace(progress_mode(err, options.quiet), err, plans.size(), planned_work);
  // Equal-time plans get their sample counts from pilots first.
  std::vector<const RunPlan*> to_run;
  for (const RunPlan& plan : plans) {
    to_run.push_back(&plan);
    if (!plan.seconds) continue;
    if (const SavedRun* saved = store->find(plan.id)) {
      chosen_plans.push_back(restored_choice(plan, *saved));
      to_run.back() = &chosen_plans.back();
    } else if (!(options.interrupted != nullptr && options.interrupted->load())) {
      chosen_plans.push_back(choose_samples(plan, runner, *progress));
      to_run.back() = &chosen_plans.back();
      // The pilot's choice replaces the planned count in the time left.
      progress->add_work(chosen_plans.back().total_samples() - plan.total_samples(), 0);
    }
  }
  // The journal's runs are restored; the others run.
  std::vector<const RunPlan*> pending;
  for (const RunPlan* plan : to_run) {
    if (store->find(plan->id) == nullptr) pending.push_back(plan);
  }
  if (options.interleave) {
    // Interleaved, then saved.
    std::vector<RunResult> results = execute_interleaved(pending, runner, *progress);
    std::size_t next = 0;
    for (const RunPlan* plan : to_run) {
      if (std::optional<RunRecord> restored = restored_record(*plan, *store, *progress)) {
        records.push_back(std::move(*restored));
        continue;
      }
      records.push_back(
          finished_record(*plan, std::move(results[next++]), options, *store, *progress, err));
      if (records.back().result.status == RunStatus::kNotRun) interrupted = true;
    }
  } else {
    if (options.farm != nullptr) {
      options.farm->announce(pending, runner);
    }
    for (const RunPlan* plan : to_run) {
      records.push_back(
          execute_and_test(*plan, options, runner, *store, interrupted, *progress, err));
    }
  }

  if (options.journal_only) {
    progress.reset();
    return interrupted ? kExitInterrupted : kExitOk;
  }

  // One family: the runs' tests and the pairwise comparisons, Holm at alpha (at alpha / 2 when
  // later stages may follow; they share the other half).
  std::vector<std::pair<Comparison, Verdict>> comparisons;
  if (options.compare_pairwise || options.escalate) {
    comparisons = pairwise_comparisons(records, options.compare_pairwise);
  }
  const double family_alpha = options.escalate ? options.alpha / 2.0 : options.alpha;
  std::size_t tested = 0;
  for (const RunRecord& record : records) tested += record.verdict && record.verdict->tested;
  for (const auto& [comparison, verdict] : comparisons) tested += verdict.tested;
  // Scenes are always checked by their block pyramids: these tests decide whether estimators
  // agree. Their power is stated at the threshold of the family they join.
  for (auto& blocks :
       scene_block_comparisons(records, family_alpha, tested, options.scale_requirements)) {
    comparisons.push_back(std::move(blocks));
  }
  std::vector<Verdict*> family;
  for (RunRecord& record : records) family.push_back(record.verdict ? &*record.verdict : nullptr);
  for (auto& [comparison, verdict] : comparisons) family.push_back(&verdict);
  decide_family(family, family_alpha);

  std::deque<RunPlan>& later_plans = chosen_plans;
  if (options.escalate) {
    const double stage_alpha =
        options.alpha / 2.0 / static_cast<double>(plans.size() * (kMaxStages - 1));
    for (RunRecord& record : records) {
      for (std::uint32_t stage = 2; stage <= kMaxStages && !interrupted && wants_escalation(record);
           ++stage) {
        const StageRecord earlier{.id = record.plan->id,
                                  .samples = record.plan->samples,
                                  .p_value = record.verdict->p_value,
                                  .alpha = record.verdict->alpha,
                                  .result = record.verdict->result,
                                  .reason = record.verdict->reason};
        later_plans.push_back(with_samples(*record.plan, record.plan->samples * kEscalationFactor));
        progress->add_work(later_plans.back().total_samples(), 1);
        RunRecord next = execute_and_test(later_plans.back(), options, runner, *store, interrupted,
                                          *progress, err);
        if (next.verdict) {
          std::vector<Verdict*> alone = {&*next.verdict};
          decide_family(alone, stage_alpha);
        }
        next.earlier_stages = std::move(record.earlier_stages);
        next.earlier_stages.push_back(earlier);
        record = std::move(next);
      }
    }
  }

  progress.reset();  // clears the terminal line before the summary

  ReportSections sections;
  std::vector<Comparison> finished;
  for (auto& [comparison, verdict] : comparisons) {
    finish_comparison(comparison, verdict);
    finished.push_back(comparison);
  }
  sections.comparisons = comparisons_json(finished);
  sections.efficiency_ratios = efficiency_ratios_json(records, options.interleave);
  if (!options.quiet) {
    print_summary(records, out);
    for (const Comparison& c : finished) {
      out << fmt::format("  compared {} on {}: {}{} ({})\n", c.estimator, c.integrand, c.result,
                         c.result == c.expect ? "" : fmt::format(" (expected {})", c.expect),
                         c.reason);
    }
    for (const std::string& line : scene_power_lines(finished)) out << "  " << line << "\n";
    if (options.interleave) print_efficiency_ratios(sections.efficiency_ratios, out);
  }
  bool published = false;
  try {
    const ReferenceCache cache(options.reference_cache);
    write_scene_images(records, folder, &cache, options.replicate_images, err);
    Context context = session_context(options);
    if (options.resume) {
      context.restored_runs = store->restored();
    }
    if (options.farm != nullptr) context.ranks = rank_count();
    published = publish_report(options, folder, context, records, sections, out, err);
  } catch (const std::exception& e) {
    err << "pcbench: error: cannot write the images of " << folder.string() << ": " << e.what()
        << "\n";
  }
  if (!published) return kExitRunFailed;
  if (interrupted) {
    err << fmt::format(
        "pcbench: interrupted; the finished runs are saved in {}: the same command with --out {} "
        "--resume runs the rest\n",
        store->directory().string(), folder.string());
  } else {
    store->discard(err);  // the report holds every run now
  }

  bool differs = false;
  bool failed = false;
  for (const RunRecord& record : records) {
    if (record.verdict && record.verdict->result != record.verdict->expect) differs = true;
    if (record.result.status == RunStatus::kError || record.result.status == RunStatus::kInvalid) {
      failed = true;
    }
  }
  for (const Comparison& c : finished) {
    if (c.result != c.expect) differs = true;
  }
  if (interrupted) return kExitInterrupted;
  if (differs) return kExitVerdictDiffers;
  if (failed) return kExitRunFailed;
  return kExitOk;
}

}  // namespace pcbench
