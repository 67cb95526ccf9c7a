// The estimator interface: one estimate of I per camera sample, computed for a batch of camera
// samples at a time (samples of a batch may share one pool of light paths).
//
// Every estimator of the family is the seed's Eq. (2): with a pool X of M light paths and K draws
// xi_k from a PMF P(xi | y, X),
//     <I> = 1/(M K) Σ_k f(x_xi_k, y) / (p(x_xi_k) p(y) P(xi_k | y, X)).
// Estimators differ in M, K and P. They record P and the draws on request (tests read the
// record); the exact check enumerates the resampling step itself (harness/verify/exact_check.h).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "base/discrete_sampler.h"
#include "base/rng.h"
#include "base/tally.h"
#include "estimators/resampling_step.h"
#include "integrands/integrand.h"

namespace pcbench {

// Work counted by estimators; summed over a run and written to the report's `counters`.
struct Counters {
  std::uint64_t camera_paths = 0;
  std::uint64_t light_paths = 0;
  std::uint64_t connections = 0;  // connections that enter the estimates (K per camera sample)
  // Evaluations of the resampling importance (with importance=f these are the only evaluations
  // of f: the chosen connections reuse them).
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
  std::vector<double> pmf = {};           // P(j | y, X) for j < M
  std::vector<std::uint32_t> draws = {};  // xi_1 .. xi_K
};

// Camera samples per estimator call. A shared pool (`pool=shared`) serves the camera samples of
// one batch, so this is part of what a shared-pool run computes, not just a tuning knob.
inline constexpr std::uint32_t kBatchSize = 256;

struct BatchContext {
  std::uint64_t key = 0;  // run_key(seed, run id)
  std::uint32_t replicate = 0;
  std::uint32_t first_sample = 0;                // a multiple of kBatchSize
  std::uint32_t sample_count = 0;                // <= kBatchSize
  Counters* counters = nullptr;                  // required
  std::vector<ResamplingRecord>* log = nullptr;  // filled when non-null (tests)
  // When not empty: the same estimator applied to |f|, one per sample (an unbiased estimate of
  // ∫∫ |f|, the scale against which a bias is judged small or not).
  std::span<double> magnitudes = {};

  std::uint32_t batch_index() const { return first_sample / kBatchSize; }
  StreamId stream(StreamPurpose purpose) const {
    return {.key = key, .replicate = replicate, .purpose = purpose};
  }
};

// Scratch memory an estimator reuses across batches on one thread.
struct EstimatorScratch {
  std::vector<PathPair> candidate_pairs;   // every (pool path, camera path) pair of a batch
  std::vector<PathPair> importance_pairs;  // the pairs whose importance guides the draws
  std::vector<double> importances;
  std::vector<double> weight_targets;     // the targets reuse's MIS weights see (a control's)
  std::vector<double> candidate_values;   // f of every candidate, when known
  std::vector<double> contributions;      // f / (p(x) p(y)) of every candidate, when known
  std::vector<double> pmf;                // P(j | y, X) of one camera sample
  std::vector<std::uint32_t> draws;       // the draws of one camera sample
  std::vector<Term> terms;                // the weighted draws of every camera sample
  std::vector<std::size_t> term_offsets;  // sample i's terms: [offsets[i], offsets[i + 1])
  std::vector<PathPair> pairs;            // the connections of the terms
  std::vector<double> values;             // f of each connection
  DiscreteSampler sampler;                // rebuilt per camera sample, memory kept
};

class Estimator {
 public:
  virtual ~Estimator() = default;

  // Writes estimates[i] for camera sample ctx.first_sample + i, i < ctx.sample_count.
  virtual void estimate_batch(const BatchContext& ctx, PathWorkspace& paths,
                              EstimatorScratch& scratch, std::span<double> estimates) const = 0;

  // The runner's fast path: adds the estimates of ctx's samples to `tally` (sample
  // ctx.first_sample + i as index) and their magnitudes to `magnitudes`, in sample order and
  // with the same bits as estimate_batch's would be added, and counts the same work, without
  // the generic steps (stored paths, pairs, terms) where an estimator's samples need none of
  // them. Returns false, having done nothing, where there is no such path (the default); the
  // caller then calls estimate_batch. Never records a resampling log.
  virtual bool tally_batch(const BatchContext& /*ctx*/, PathWorkspace& /*paths*/, Tally& /*tally*/,
                           CompensatedSum& /*magnitudes*/) const {
    return false;
  }

  // Whether the per-sample estimates of one replicate are independent (no shared pool): only
  // then is a within-replicate variance meaningful (docs/reference/INTERFACE.md, "replicate").
  virtual bool samples_independent() const { return true; }
};

}  // namespace pcbench
