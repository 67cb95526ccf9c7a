// The estimator family of probabilistic connections (Popov et al., "Probabilistic Connections for
// Bidirectional Path Tracing", CGF 34(4), EGSR 2015): a pool X of M light paths, K connections
// chosen from it, and the estimate
//     <I> = 1/(M K) Σ_k f(x_ξk, y) / (p(x_ξk) p(y) P(ξk | y, X)).
// One code path samples the pool, chooses connections and weights them (the choosing and
// weighting is estimators/resampling_step.h); the estimators differ only in how they choose
// (the registry names each configuration):
//
//   plain   M = K = 1, P = 1: one fresh light path per camera sample (plain BDPT).
//   vc-all  every path of the pool once, P = 1/M (K = M systematic draws: E[count_j] = K P_j = 1,
//           which is all the unbiasedness proof needs); estimate (1/M) Σ_j f / (p(x_j) p(y)).
//   lvc     K uniform draws with replacement from the pool's light vertices, P = 1/N_v (an
//           analytic light path is one vertex: N_v = M); the light-vertex-cache variant.
//   pcbpt   K draws, P(j) = (1 - u) w_j / Σ w + u / M, w_j = w(x_j, y) the resampling importance
//           and u = uniform_mix (Popov et al. 2015, Sec. 4). P > 0 wherever w > 0, and
//           everywhere when u > 0.
//
// Parameters (those an estimator reads are listed in its registry entry):
//   M            light paths in a pool (default 16)
//   K            draws per camera sample (default 4)
//   pool         fresh: a new pool per camera sample (the paper's setup); shared: one pool per
//                batch of 256 camera samples, as a renderer shares one per iteration
//   importance   approx: the integrand's cheap approximation (|f| when it has none); f: |f|
//                itself; uniform: w = 1; cached: |f| at the cache point of the camera sample's
//                cell (cache_cells per dimension), as PCBPT caches per screen tile; adversarial:
//                1 / (0.01 + a / max a) for the approximation a, positive but large where f is
//                small
//   uniform_mix  u above (default 0.1)
//   draws        independent (with replacement, the default), stratified or systematic (through
//                the inverse CDF); all three draw each j K P_j times in expectation
//   sampler      cdf (binary search, the default) or alias (Vose, O(1) per draw), for independent
//                draws. Building the table costs more than the K draws unless K is comparable to
//                M: measured with `pcbench_bench --benchmark_filter=BuildAndDraw`, building and
//                drawing K = 4 from M = 4096 takes 7 µs by CDF and 27 µs by alias, and CDF is
//                ahead for every measured M >= 256 even at K = 64.
#pragma once

#include <cstdint>

#include "estimators/estimator.h"
#include "estimators/resampling_step.h"

namespace pcbench {

enum class PoolMode { kFresh, kShared };
enum class ImportanceSource { kApproximate, kF, kUniform, kCached, kAdversarial };

struct ResamplingConfig {
  StepConfig step = {};
  PoolMode pool = PoolMode::kFresh;
  ImportanceSource importance = ImportanceSource::kApproximate;
  std::uint32_t cache_cells = 4;  // per camera dimension, for ImportanceSource::kCached
};

// The pools of a batch with everything the resampling step may need, as prepared for one part
// of a batch: shared by the estimator and the exact check (harness/verify/exact_check.h).
struct PreparedPools {
  std::uint32_t samples = 0;
  std::uint32_t M = 0;
  bool shared = false;
  std::uint32_t pool_start(std::uint32_t i) const { return shared ? 0u : i * M; }
};

// The weighted terms of a part of a batch, as every estimator of terms (the family, the reservoir
// estimators) turns them into estimates. Before the first sample: scratch.terms, .pairs cleared
// and .term_offsets = {0}.
// Closes camera sample i's terms (appended since its last offset): each a connection to path
// pool_start + index.
void close_sample_terms(EstimatorScratch& scratch, std::uint32_t pool_start, std::uint32_t i);
// f of each connection (from scratch.candidate_values, pool stride m, when known), then per
// sample Σ coefficient × f / (p(x) p(y)) into `estimates` (and with |f| into ctx.magnitudes);
// counts the connections.
void sum_terms(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
               std::uint32_t m, std::span<double> estimates);

class ResamplingEstimator final : public Estimator {
 public:
  explicit ResamplingEstimator(const ResamplingConfig& config)
      : config_(config), step_(config.step) {}

  void estimate_batch(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                      std::span<double> estimates) const override;
  // Plain and vertex connection on fresh pools (every path once, no log): the workspace's fused
  // loop (PathWorkspace::tally_every_path), where it has one.
  bool tally_batch(const BatchContext& ctx, PathWorkspace& paths, Tally& tally,
                   CompensatedSum& magnitudes) const override;
  bool samples_independent() const override { return config_.pool == PoolMode::kFresh; }

  const ResamplingConfig& config() const { return config_; }
  const ResamplingStep& step() const { return step_; }

  // Samples the camera paths and pools of ctx's samples and evaluates what the step needs
  // (importances; f of every candidate when `with_contributions` or the step needs it), into
  // `scratch`. pool_view(i) then describes camera sample i's pool.
  PreparedPools prepare(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                        bool with_contributions) const;
  PoolView pool_view(const PreparedPools& pools, const EstimatorScratch& scratch,
                     std::uint32_t i) const;

 private:
  // Candidate pairs (camera samples × pool paths) handled at once; bounds the scratch memory.
  static constexpr std::uint32_t kMaxCandidates = 1u << 20;

  // estimate_batch for a part of a batch with at most kMaxCandidates candidate pairs.
  void estimate_part(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                     std::span<double> estimates) const;
  void estimate_every_path(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                           const PreparedPools& pools, std::span<double> estimates) const;
  void evaluate_importance(const PreparedPools& pools, PathWorkspace& paths,
                           EstimatorScratch& scratch) const;

  ResamplingConfig config_;
  ResamplingStep step_;
};

}  // namespace pcbench
