// The JSON report (schema: results/report.schema.json, schema_version 1).
//
// Non-finite numbers are written as null *and* named in the run's `nonfinite_fields` (JSON has
// no NaN; nlohmann-json would write null without a word). Reports are written to a temporary
// file in the same folder and renamed, so a reader never sees half a report.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/verify/exact_check.h"
#include "harness/verify/run_record.h"
#include "results/context.h"

namespace pcbench {

inline constexpr int kSchemaVersion = 1;

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

}  // namespace pcbench
