// The exact check of the resampling step (`pcbench verify --exact`): no sampling error at all.
//
// For a few random (y, X) cases, every sequence of draws the estimator can make is enumerated
// with its probability, and the expectation over the draws is compared with connecting to the
// whole pool, (1/M) Σ_j f(x_j, y) / (p(x_j) p(y)). The two agree for every (y, X) exactly when
// the resampling step is unbiased; a disagreement beyond rounding is a proof of bias, found in
// milliseconds. It also counts support violations (f != 0 where P = 0) and compares the expected
// number of times each j is drawn with K P_j, the property the unbiasedness proof rests on.
//
// Enumeration visits up to M^K sequences per case, so pools are cut to M <= 6 and K <= 3; the
// result says which M and K were checked.
//
// The reservoir estimators (ris, restir and the reuse controls, estimators/reservoir_estimator.h)
// are checked the same way: every camera sample of one batch is a case, and every sequence of
// reservoir choices its estimate reads (its own reservoirs, and for reuse those of its neighbours
// and of every round) is enumerated with its probability. Reuse is cut further, to N <= 2 / rounds
// and rounds <= 2.
#pragma once

#include <cstdint>
#include <string>

#include "harness/plan/plan.h"

namespace pcbench {

inline constexpr std::uint32_t kExactMaxM = 6;
inline constexpr std::uint32_t kExactMaxK = 3;
inline constexpr std::uint32_t kExactCases = 64;
inline constexpr std::uint32_t kExactMaxNeighbours = 2;
inline constexpr std::uint32_t kExactMaxRounds = 2;
// Rounding tolerance, relative to the expected sum of |terms| (Σ |f| / P over the draws).
inline constexpr double kExactTolerance = 1e-9;

struct ExactCheck {
  bool applicable = false;  // false: not a resampling estimator (reason says why)
  std::uint32_t M = 0;      // as checked
  std::uint32_t K = 0;
  std::uint32_t cases = 0;
  std::uint64_t sequences = 0;             // draw sequences enumerated over all cases
  std::uint32_t expectation_failures = 0;  // cases whose expectation misses connect-to-all
  double max_scaled_error = 0.0;           // max |E[estimate] - connect-all| / Σ|terms| scale
  std::uint32_t support_violations = 0;    // (case, j) with f != 0 and P = 0
  double max_multiplicity_error = 0.0;     // max |E[count_j] - K P_j|
  std::string result;                      // consistent | biased | inconclusive
  std::string reason;
};

// Checks the plan's estimator on the plan's integrand, the cases drawn from `seed`.
ExactCheck exact_check(const RunPlan& plan, std::uint64_t seed);

// The exact check of one planned run (`verify --exact`) and what it was expected to find.
struct ExactRecord {
  const RunPlan* plan = nullptr;
  ExactCheck check = {};
  std::string expect = {};
};

}  // namespace pcbench
