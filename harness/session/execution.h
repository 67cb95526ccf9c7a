// The first steps of a session (harness/session/session.h): choosing the budgets of equal-time
// plans by pilots, then executing the runs (interleaved, over the ranks of an MPI farm, or one by
// one), each saved to the journal and tested alone. The family's correction comes later
// (harness/session/family_test.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <iosfwd>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/run/progress.h"
#include "harness/run/run_store.h"
#include "harness/run/runner.h"
#include "harness/session/session.h"
#include "harness/verify/run_record.h"

namespace pcbench {

// What every run of a session goes through: the session's options and its one RunnerOptions, the
// journal that saves each finished run (and holds those of a resumed session), the progress
// line, and the stream for diagnoses.
struct RunServices {
  const SessionOptions& options;
  const RunnerOptions& runner;
  RunStore& store;
  ProgressReporter& progress;
  std::ostream& err;
};

// The samples × replicates of the plans the journal does not hold yet: the work the progress
// line starts with.
std::uint64_t work_to_do(const std::vector<RunPlan>& plans, const RunStore& store);

// Choose budgets: the plans to run, in order, an equal-time plan replaced by its pilot's choice of
// samples (or by the choice its saved run records). The chosen plans are made in `chosen`, whose
// addresses stay valid for the records that point at them. After Ctrl-C no pilot starts: the plan
// stays as it is and is reported not run.
std::vector<const RunPlan*> choose_budgets(const std::vector<RunPlan>& plans,
                                           std::deque<RunPlan>& chosen,
                                           const RunServices& services);

// The runs of a session, each tested alone, and whether Ctrl-C stopped any.
struct ExecutedRuns {
  std::vector<RunRecord> records;  // one per plan, in the plans' order
  bool interrupted = false;
};

// Execute: every plan run (or restored from the journal), saved and tested alone. With
// options.interleave the runs take their replicates in turn (harness/run/interleaved_runs.h); with
// an MPI farm its ranks compute the replicates; else one run after another.
ExecutedRuns execute_runs(const std::vector<const RunPlan*>& plans, const RunServices& services);

// One plan run (or restored from the journal), saved and tested alone; a later stage of
// escalation is one too. Sets `interrupted` when Ctrl-C stopped it, and runs nothing once set.
RunRecord execute_and_test(const RunPlan& plan, bool& interrupted, const RunServices& services);

}  // namespace pcbench
