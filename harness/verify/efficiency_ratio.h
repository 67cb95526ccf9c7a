// Equal-cost comparison of two runs on one integrand: the ratio of their efficiencies with an
// interval, from replicates measured interleaved in one process (harness/run/interleaved_runs.h).
//
// Efficiency is 1 / (variance × cost). With the spread across replicates
// (docs/reference/INTERFACE.md: every standard error uses it) a run's efficiency is 1 / (s² c),
// s² the variance of its replicate estimates and c its CPU seconds per replicate, whatever its
// sample count. The ratio of b to a
//
//     ratio = (s²_a / s²_b) · (c_a / c_b)
//
// has two uncertain factors. The variance factor: (s²_a/σ²_a)/(s²_b/σ²_b) ~ F(R_a − 1, R_b − 1)
// for normal replicate estimates (each a mean of many samples). The cost factor: the geometric
// mean of the paired replicates' c_a,r / c_b,r, with a Student t interval on the log ratios
// (pairing cancels what the machine was doing at the time, which is why the runs interleave).
// Each factor gets a 97.5% interval; their product covers the ratio with at least 95%
// (Bonferroni).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/verify/run_record.h"

namespace pcbench {

inline constexpr double kEfficiencyRatioLevel = 0.95;

struct EfficiencyRatio {
  double ratio = 0.0;  // efficiency of b / efficiency of a
  double low = 0.0;    // at least kEfficiencyRatioLevel coverage
  double high = 0.0;
  double variance_ratio = 0.0;  // s²_a / s²_b
  double variance_low = 0.0, variance_high = 0.0;
  double cost_ratio = 0.0;  // c_a / c_b, geometric mean over paired replicates
  double cost_low = 0.0, cost_high = 0.0;
  std::uint32_t pairs = 0;  // replicates paired for the cost
  bool valid = false;       // false when either run has fewer than 2 replicates or no spread
};

// `estimates_*`: the runs' replicate estimates; `cpu_*`: their CPU seconds per replicate, in
// replicate order (replicate r of a ran next to replicate r of b).
EfficiencyRatio efficiency_ratio(std::span<const double> estimates_a, std::span<const double> cpu_a,
                                 std::span<const double> estimates_b,
                                 std::span<const double> cpu_b);

// Per group of finished analytic runs on one integrand: each run's efficiency relative to the
// group's first honest run, in the report's `efficiency_ratios` form. Scenes are left out: the
// variance of their image means is not their image error (their `image` section gives the
// relative MSE at equal time instead).
nlohmann::json efficiency_ratios_json(const std::vector<RunRecord>& records, bool interleaved);

}  // namespace pcbench
