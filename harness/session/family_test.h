// A session's runs and comparisons tested as one family (harness/session/session.h), and
// escalation: later stages of the runs the family left undecided.
#pragma once

#include <deque>
#include <utility>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/session/execution.h"
#include "harness/session/session.h"
#include "harness/verify/report_compare.h"
#include "harness/verify/run_record.h"
#include "harness/verify/statistics.h"

namespace pcbench {

// Test the family: the runs' tests against their references, the pairwise comparisons (every
// pair with options.compare_pairwise; under escalation, pairs on integrands without a reference)
// and the block pyramids of the scene runs, decided together by Holm at options.alpha (at
// alpha / 2 under escalation: the later stages share the other half). Sets each record's
// adjusted verdict; returns the comparisons with theirs.
std::vector<std::pair<Comparison, Verdict>> test_family(std::vector<RunRecord>& records,
                                                        const SessionOptions& options);

// Escalate (options.escalate): a borderline or low-count run is run again with kEscalationFactor
// times the samples, up to kMaxStages stages, each later stage tested alone at an even
// (Bonferroni) share of the other alpha / 2 over every possible later stage of every run. The
// later stage replaces the record, which keeps the earlier ones in earlier_stages; the later
// plans are made in `later_plans` (stable addresses). Nothing more runs once interrupted.
void escalate(ExecutedRuns& runs, std::deque<RunPlan>& later_plans, const RunServices& services);

}  // namespace pcbench
