// A finished run as saved for `--resume`: everything the session tests and reports from (the
// RunResult, down to the tail buffers, series checkpoints, scene images and strategy images)
// plus the budget an equal-time pilot chose, in a JSON form that reads back bit for bit.
//
// Numbers are written in the shortest form that reads back to the same double; the non-finite
// ones JSON cannot hold are written as the strings "nan", "inf" and "-inf". A restored run is
// then indistinguishable from one that has just run: the session derives its aggregates,
// diagnostics, verdict, comparisons and escalation from the same bits.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "harness/run/runner.h"

namespace pcbench {

inline constexpr const char* kSavedRunFormat = "pcbench-saved-run";
inline constexpr int kSavedRunVersion = 1;

struct SavedRun {
  std::string id;  // the plan's id (as requested: an equal-time run keeps its seconds id)
  std::uint64_t seed = 0;
  std::uint64_t samples = 0;  // as run (an equal-time run: as its pilot chose)
  std::uint32_t replicates = 0;
  std::uint64_t pilot_samples = 0;
  double pilot_cpu_per_sample = 0.0;
  RunResult result;
};

// A double as JSON that reads back to the same bits: a number, or "nan", "inf", "-inf" (also
// what `pcbench replay --json` prints).
nlohmann::ordered_json exact_number(double value);

// One line of JSON (a 128×128 scene run's images make it megabytes; nobody reads it by eye).
std::string saved_run_text(const SavedRun& run);

// Reads what saved_run_text wrote. Throws std::runtime_error (or nlohmann::json::exception) on
// anything else; the caller names the file.
SavedRun read_saved_run(const std::string& text);

}  // namespace pcbench
