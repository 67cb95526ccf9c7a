// Equal-time budgets (`--seconds T`): a short pilot measures what one sample of a run costs in
// CPU seconds, and the run then takes a fixed sample count from it. The run never stops on a
// clock mid-way: that would bias estimators whose cost correlates with their value.
#pragma once

#include "harness/plan.h"
#include "harness/progress.h"
#include "harness/runner.h"
#include "harness/saved_run.h"

namespace pcbench {

// An equal-time plan with its sample count chosen by a pilot run now (random numbers of their
// own, never the run's), which the progress log reports.
RunPlan choose_samples(const RunPlan& plan, const RunnerOptions& options,
                       ProgressReporter& progress);

// An equal-time plan restored from the journal: the sample count its pilot chose then (a new
// pilot would measure another machine load, hence another N and other numbers).
RunPlan restored_choice(const RunPlan& plan, const SavedRun& saved);

}  // namespace pcbench
