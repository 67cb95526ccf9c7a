// Equal-time budgets (`--seconds T`): a short pilot measures what one sample of a run costs in
// CPU seconds, and the run then takes a fixed sample count from it. The run never stops on a
// clock mid-way: that would bias estimators whose cost correlates with their value.
//
// A sample is one camera sample of an analytic run and one sample per pixel of a scene (one
// iteration over the whole image); T is CPU seconds per replicate for both.
#pragma once

#include <cstdint>

#include "harness/plan/plan.h"
#include "harness/run/progress.h"
#include "harness/run/runner.h"
#include "harness/run/saved_run.h"

namespace pcbench {

// What a pilot runs for one kind of run, and which sample counts it may choose.
struct PilotRule {
  std::uint64_t samples = 0;  // per pilot replicate (the pilot takes 2 replicates)
  std::uint64_t step = 1;     // N is a whole number of these
  std::uint64_t least = 1;    // and at least this; also N when the pilot measured nothing
  const char* unit = "";      // one sample, in words, for the progress log
  const char* units = "";     // several
};

// The rule for `plan`: analytic or scene.
const PilotRule& pilot_rule(const RunPlan& plan);

// The sample count `seconds` buys at `cpu_per_sample`: floor(seconds / cost) rounded down to
// whole steps, within [rule.least, kMaxSamples]; rule.least when the cost is not a positive
// number.
std::uint64_t samples_for_seconds(const PilotRule& rule, double seconds, double cpu_per_sample);

// An equal-time plan with its sample count chosen by a pilot run now (random numbers of their
// own, never the run's), which the progress log reports.
RunPlan choose_samples(const RunPlan& plan, const RunnerOptions& options,
                       ProgressReporter& progress);

// An equal-time plan restored from the journal: the sample count its pilot chose then (a new
// pilot would measure another machine load, hence another N and other numbers).
RunPlan restored_choice(const RunPlan& plan, const SavedRun& saved);

}  // namespace pcbench
