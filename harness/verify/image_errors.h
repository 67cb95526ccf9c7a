// The errors of a scene run's images against a reference image: RMSE, relative MSE, and the
// relative MSE one CPU second buys (equal time).
//
// A reference that is itself a Monte Carlo image (a cached converged image, or another run's
// mean) adds its own variance to every squared error: E[(x − ref)²] = MSE(x) + Var(ref) for
// independent x and ref. The errors here subtract the reference's estimated variance (its
// standard error squared, per value), so that they measure the run and not the reference, and
// report that share as `reference_rel_variance`: when it is not small against the run's own
// error, the reference is not converged enough to rank estimators.
#pragma once

#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/run/runner.h"
#include "results/image.h"

namespace pcbench {

// `replicates` are the run's images and `results` their replicate records (for CPU time);
// `mean` their mean. `reference_stderr` is null for an exact reference.
nlohmann::ordered_json image_error_fields(std::span<const Image> replicates,
                                          std::span<const ReplicateResult> results,
                                          const Image& mean, const Image& reference,
                                          const Image* reference_stderr);

}  // namespace pcbench
