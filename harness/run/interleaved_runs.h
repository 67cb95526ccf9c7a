// `--interleave`: the runs on one integrand are taken replicate by replicate in turn (replicate
// 0 of every run, then replicate 1, ...), so that whatever else the machine does falls on all of
// them alike, and their costs can be compared as ratios with intervals (harness/run/
// efficiency_ratio.h). The numbers are those of runs taken one after the other: a replicate's
// random streams depend only on its index.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/run/progress.h"
#include "harness/run/runner.h"

namespace pcbench {

// Indices of `plans` grouped by integrand and integrand parameters, groups in order of first
// appearance: the runs that integrate the same function.
std::vector<std::vector<std::size_t>> same_integrand_groups(
    const std::vector<const RunPlan*>& plans);

// Every plan's result, taken interleaved within its group. A run cut short by an interrupt is
// not_run, as in a plain session.
std::vector<RunResult> execute_interleaved(const std::vector<const RunPlan*>& plans,
                                           const RunnerOptions& base, ProgressReporter& progress);

}  // namespace pcbench
