// Suite files (docs/reference/INTERFACE.md, "Suite file"):
//   {"name", "description", "defaults": {"samples", "replicates", "seed"},
//    "runs": [{"estimator", "integrand", "params": {..}, "samples", "replicates", "expect"}],
//    "grid": [{"estimator": [..], "integrand": [..], "params": {"M": [..]}, ...}],
//    "compare", "interleave", "strategy_images", "require_mdb": {"tile": 0.05, "image": 0.01}}
// Errors name the file, the JSON pointer of the offending value and the valid keys.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/plan/scale_requirements.h"

namespace pcbench {

struct SuiteRequest {
  std::string name;
  std::vector<GridRequest> grids;  // rows of "runs" first, then "grid" entries, in file order
  std::optional<std::uint64_t> samples;
  std::optional<double> seconds;  // equal-time default
  std::optional<std::uint32_t> replicates;
  std::optional<std::uint64_t> seed;
  // "compare": "pairwise": two-sample tests between every pair of runs on the same integrand
  // (same parameters), counted in the family-wise alpha and the exit status.
  bool compare_pairwise = false;
  // "interleave": true: runs on one integrand take their replicates in turn (--interleave).
  bool interleave = false;
  // "paired": true: scene runs share their random streams between estimators and their block
  // pyramids are paired tests (--paired; RunPlan::paired_streams in harness/plan/plan.h).
  bool paired = false;
  // "strategy_images": true: scene runs also write their per-strategy images (--strategy-images).
  bool strategy_images = false;
  // "require_mdb": {SCALE: FRACTION}: what a scene comparison's block pyramid must detect at each
  // scale (harness/plan/scale_requirements.h), on top of the defaults.
  ScaleRequirements scale_requirements = {};
};

SuiteRequest parse_suite(const std::string& text, const std::string& file_name);
SuiteRequest load_suite(const std::string& path);

}  // namespace pcbench
