// The estimator interface: one estimate of I per camera sample, computed for a batch of camera
// samples at a time (samples of a batch may share one pool of light paths).
//
// Every estimator of the family is the seed's Eq. (2): with a pool X of M light paths and K draws
// xi_k from a PMF P(xi | y, X),
//     <I> = 1/(M K) Σ_k f(x_xi_k, y) / (p(x_xi_k) p(y) P(xi_k | y, X)).
// Estimators differ in M, K and P. They record P and the draws on request, so that the verifier
// can enumerate the resampling step exactly.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "harness/rng.h"
#include "integrands/integrand.h"

namespace pcbench {

// Work counted by estimators; summed over a run and written to the report's `counters`.
struct Counters {
  std::uint64_t camera_paths = 0;
  std::uint64_t light_paths = 0;
  std::uint64_t connections = 0;  // evaluations of f
  std::uint64_t importance_evaluations = 0;

  void add(const Counters& other) {
    camera_paths += other.camera_paths;
    light_paths += other.light_paths;
    connections += other.connections;
    importance_evaluations += other.importance_evaluations;
  }
};

// The resampling step of one camera sample, as made: P over the pool and the pool indices drawn.
struct ResamplingRecord {
  std::uint32_t sample = 0;
  std::vector<double> pmf;           // P(j | y, X) for j < M
  std::vector<std::uint32_t> draws;  // xi_1 .. xi_K
};

struct BatchContext {
  std::uint64_t key = 0;  // run_key(seed, run id)
  std::uint32_t replicate = 0;
  std::uint32_t first_sample = 0;
  std::uint32_t sample_count = 0;
  Counters* counters = nullptr;                  // required
  std::vector<ResamplingRecord>* log = nullptr;  // filled when non-null (verification)

  StreamId stream(StreamPurpose purpose) const {
    return {.key = key, .replicate = replicate, .purpose = purpose};
  }
};

// Scratch memory an estimator reuses across batches on one thread.
struct EstimatorScratch {
  std::vector<PathPair> pairs;
  std::vector<double> values;
};

class Estimator {
 public:
  virtual ~Estimator() = default;

  // Writes estimates[i] for camera sample ctx.first_sample + i, i < ctx.sample_count.
  virtual void estimate_batch(const BatchContext& ctx, PathWorkspace& paths,
                              EstimatorScratch& scratch, std::span<double> estimates) const = 0;
};

}  // namespace pcbench
