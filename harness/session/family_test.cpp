#include "harness/session/family_test.h"

#include <cstddef>
#include <cstdint>

#include "harness/verify/rounding_bound.h"
#include "harness/verify/scene_verification.h"

namespace pcbench {
namespace {

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

// How many tests of the family were made so far (an untested verdict does not count).
std::size_t tested_count(const std::vector<RunRecord>& records,
                         const std::vector<std::pair<Comparison, Verdict>>& comparisons) {
  std::size_t tested = 0;
  for (const RunRecord& record : records) tested += record.verdict && record.verdict->tested;
  for (const auto& [comparison, verdict] : comparisons) tested += verdict.tested;
  return tested;
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

// The stages of one run after the first, while it wants them: each with kEscalationFactor times
// the samples of the one before, tested alone at `stage_alpha`.
void escalate_run(RunRecord& record, double stage_alpha, bool& interrupted,
                  std::deque<RunPlan>& later_plans, const RunServices& services) {
  for (std::uint32_t stage = 2; stage <= kMaxStages && !interrupted && wants_escalation(record);
       ++stage) {
    later_plans.push_back(with_samples(*record.plan, record.plan->samples * kEscalationFactor));
    services.progress.add_work(later_plans.back().total_samples(), 1);
    RunRecord next = execute_and_test(later_plans.back(), interrupted, services);
    if (next.verdict) {
      std::vector<Verdict*> alone = {&*next.verdict};
      decide_family(alone, stage_alpha);
    }
    next.earlier_stages = std::move(record.earlier_stages);
    record.earlier_stages.clear();
    next.earlier_stages.push_back(std::move(record));
    record = std::move(next);
  }
}

}  // namespace

std::vector<std::pair<Comparison, Verdict>> test_family(std::vector<RunRecord>& records,
                                                        const SessionOptions& options) {
  std::vector<std::pair<Comparison, Verdict>> comparisons;
  if (options.compare_pairwise || options.escalate) {
    comparisons = pairwise_comparisons(records, options.compare_pairwise);
  }
  const double family_alpha = options.escalate ? options.alpha / 2.0 : options.alpha;
  // Scenes are always checked by their block pyramids: these tests decide whether estimators
  // agree. Their power is stated at the threshold of the family they join.
  for (auto& blocks : scene_block_comparisons(
           records, family_alpha, tested_count(records, comparisons), options.scale_requirements)) {
    comparisons.push_back(std::move(blocks));
  }
  std::vector<Verdict*> family;
  for (RunRecord& record : records) family.push_back(record.verdict ? &*record.verdict : nullptr);
  for (auto& [comparison, verdict] : comparisons) family.push_back(&verdict);
  decide_family(family, family_alpha);
  return comparisons;
}

void escalate(ExecutedRuns& runs, std::deque<RunPlan>& later_plans, const RunServices& services) {
  // One record per planned run: the other half of alpha split over all their later stages.
  const double stage_alpha =
      services.options.alpha / 2.0 / static_cast<double>(runs.records.size() * (kMaxStages - 1));
  for (RunRecord& record : runs.records) {
    escalate_run(record, stage_alpha, runs.interrupted, later_plans, services);
  }
}

}  // namespace pcbench
