// A tested run as the session keeps it: its plan, its result, the figures and the verdict the
// verification layer computed from it, and for an escalated run the stages before the last.
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

// An earlier stage of an escalated run: its budget and what its test said.
struct StageRecord {
  std::string id = {};
  std::uint64_t samples = 0;
  double p_value = 0.0;
  double alpha = 0.0;  // the threshold the stage's (adjusted) p-value was compared with
  std::string result = {};
  std::string reason = {};
};

struct RunRecord {
  const RunPlan* plan = nullptr;
  std::vector<StageRecord> earlier_stages = {};  // sequential escalation, first stage first
  RunResult result;
  Aggregates aggregates;
  SampleDiagnostics diagnostics;
  std::optional<Verdict> verdict;                    // absent for runs that did not finish
  std::optional<nlohmann::ordered_json> image = {};  // scenes: the image section, schema form
};

}  // namespace pcbench
