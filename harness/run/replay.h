// `pcbench replay`: re-evaluates one camera sample of a run, with the same random streams, and
// shows what went into its estimate (the camera path, the pool, P and the draws), so that a
// non-finite sample found in a run of millions can be stepped into in a debugger.
//
// Every random number is keyed by (seed, run id, replicate, purpose, sample or batch, path), so
// evaluating the sample's batch reproduces the run's estimate exactly; the run id is rebuilt
// from estimator, integrand, effective parameters, samples and replicates, all of which the
// printed command carries.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/run/runner.h"

namespace pcbench {

// The command that replays sample `where` of `plan`, or nothing where the run's samples are not
// camera samples of an analytic integrand (a scene's replicate is a whole image).
std::optional<std::string> replay_command(const RunPlan& plan, const NonfiniteLocation& where);

struct ReplayedPath {
  double pdf = 0.0;
  std::vector<double> coordinates = {};  // empty where the integrand does not expose them
};

struct ReplayedCandidate {
  ReplayedPath path;
  double f = 0.0;             // f(x_j, y)
  double contribution = 0.0;  // f / (p(x_j) p(y))
};

struct ReplayedSample {
  std::uint64_t batch_first = 0;  // the batch the runner evaluated the sample in
  std::uint32_t batch_count = 0;
  double estimate = 0.0;        // as the run tallied it: its batch evaluated as the runner does
  double estimate_alone = 0.0;  // the sample evaluated alone, where the details below come from
  ReplayedPath camera;
  std::vector<ReplayedCandidate> pool;  // the sample's pool (a shared pool: its batch's)
  std::vector<double> pmf;              // P(j | y, X)
  std::vector<std::uint32_t> draws;     // ξ_1 .. ξ_K
};

// Throws InputError for a scene, or a replicate or sample outside the run.
ReplayedSample replay_sample(const RunPlan& plan, std::uint64_t seed, std::uint32_t replicate,
                             std::uint64_t sample);

// Prints a replayed sample (JSON with `json`). `run_id`, when given, must be the id the streams
// are keyed by (replay_command passes it), so that a command edited by hand cannot replay
// another run unnoticed. Exit status 3 when the estimate is not finite, 0 otherwise.
int run_replay(const RunPlan& plan, std::uint64_t seed, std::uint32_t replicate,
               std::uint64_t sample, const std::optional<std::string>& run_id, bool json,
               std::ostream& out);

}  // namespace pcbench
