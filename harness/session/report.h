// The JSON report (schema: results/report.schema.json, schema_version 1).
//
// Non-finite numbers are written as null *and* named in the run's `nonfinite_fields` (JSON has
// no NaN; nlohmann-json would write null without a word). Reports are written to a temporary
// file in the same folder and renamed, so a reader never sees half a report.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/verify/exact_check.h"
#include "harness/verify/statistics.h"
#include "results/context.h"

namespace pcbench {

inline constexpr int kSchemaVersion = 1;

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

// The exact check of one planned run (`verify --exact`) and what it was expected to find.
struct ExactRecord {
  const RunPlan* plan = nullptr;
  ExactCheck check = {};
  std::string expect = {};
};

// The report's optional parts besides the runs.
struct ReportSections {
  nlohmann::json comparisons = nlohmann::json::array();  // already in the schema's form
  std::vector<ExactRecord> exact_checks = {};
  std::optional<nlohmann::json> calibration = {};
  // `pcbench calibrate` on scenes (harness/commands/tile_calibration.h).
  std::optional<nlohmann::json> tile_calibration = {};
  nlohmann::json external = nlohmann::json::array();  // verify --estimates, in the schema's form
  nlohmann::json efficiency_ratios = nlohmann::json::array();  // harness/run/interleaved_runs.h
  std::optional<nlohmann::json> image_sets = {};  // verify --images, in the schema's form
};

std::string report_json(const Context& context, const std::string& suite_name,
                        const std::vector<RunRecord>& runs, const ReportSections& sections = {});

// A verdict in the report's form (non-finite figures written as null).
nlohmann::json verdict_to_json(const Verdict& verdict);

// Writes `text` to `path` atomically (temporary file + rename), creating parent folders.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace pcbench
