// A tested run as the session keeps it: its plan, its result, the figures and the verdict the
// verification layer computed from it. An escalated run is the record of its last stage, which
// keeps the records of the stages before it: each is a tested run too, with fewer samples.
// The report (harness/session/report.h) writes these; it does not define them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/verify/statistics.h"

namespace pcbench {

struct RunRecord {
  const RunPlan* plan = nullptr;
  // Sequential escalation: the earlier stages, first stage first (each with a verdict, which
  // is what escalated it, and no earlier stages of its own).
  std::vector<RunRecord> earlier_stages = {};
  RunResult result;
  Aggregates aggregates;
  SampleDiagnostics diagnostics;
  std::optional<Verdict> verdict;                    // absent for runs that did not finish
  std::optional<nlohmann::ordered_json> image = {};  // scenes: the image section, schema form
};

}  // namespace pcbench
