// The table printed after every run: one row per run.
#pragma once

#include <iosfwd>
#include <vector>

#include "harness/session/report.h"

namespace pcbench {

void print_summary(const std::vector<RunRecord>& records, std::ostream& out);

// The efficiency ratios (report form, harness/run/interleaved_runs.h), one line each.
void print_efficiency_ratios(const nlohmann::json& ratios, std::ostream& out);

}  // namespace pcbench
