// Resampled importance sampling with reservoirs and its spatial reuse, the analytic forms of
// `ris` and `restir` (estimators/ris.h and estimators/restir.h give their equations) and of the
// reuse controls: one engine, so that the exact check (harness/verify/exact_check.h) enumerates
// the code the runs execute.
//
// A camera sample t with camera path y_t has the target p̂_t(x) = p̂(x, y_t) (the integrand's
// approximation, |f| or 1) over the light paths x_j of its pool, drawn from the source density
// q = p(x). Round 0 streams the pool through a reservoir with weights w_j = p̂_t(x_j) / q(x_j)
// and keeps Y_t with the contribution weight W_t = Σ_j w_j / (M p̂_t(Y_t)) (K independent
// reservoirs for `ris`). Each later round replaces sample c's reservoir by one resampled from
// its sources S = {c, c+1, .., c+k} (mod the batch's n samples, k = min(N, n - 1)): source s
// offers its Y_s with weight ω_s = m_s(Y_s) p̂_c(Y_s) W_s (m from estimators/reuse_weights.h,
// evaluated with every source's target at Y_s), and the reservoir kept, Y, gets
// W = Σ_s ω_s / p̂_c(Y). The estimate of sample c is f(Y, y_c) W / p(y_c) (the mean over the K
// reservoirs for `ris`).
//
// Random numbers: reservoir k of sample t in round 0 reads the kResampling stream of sample t,
// path k; round r >= 1 the kEstimatorAux stream of sample t, path r. Every choice is a pure
// function of (key, counter), whatever the thread or the split of a batch.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/resampling.h"
#include "estimators/reservoir.h"
#include "estimators/reuse_weights.h"

namespace pcbench {

// The most neighbours a reuse reads (the `N` parameter's range): a sample's targets at one
// candidate then fit on the stack, with no allocation per camera sample.
constexpr std::uint32_t kMaxReuseNeighbours = 32;

struct ReservoirConfig {
  std::uint32_t M = 16;
  std::uint32_t K = 1;  // independent reservoirs per camera sample in round 0
  PoolMode pool = PoolMode::kFresh;
  ImportanceSource target = ImportanceSource::kApproximate;  // approx, f or uniform
  std::uint32_t neighbours = 0;                              // N <= kMaxReuseNeighbours
  std::uint32_t rounds = 0;                                  // 0: no reuse (ris)
  ReuseWeighting weighting = {};
  // ctl-reuse-unshadowed: the neighbours' targets in the MIS weights are
  // (1 - share) p̂ + share × the integrand's approximation, which has no visibility.
  double unshadowed_share = 0.0;
};

// A camera sample's reservoir after a round: the pool index kept (Reservoir::kEmpty: none) and
// its contribution weight W, NaN when a weight was not finite.
struct ReservoirSample {
  std::uint32_t index = Reservoir::kEmpty;
  double W = 0.0;
};

// Where each choice comes from: a sampled reservoir in a run, every possible outcome in turn in
// the exact check. `pick` streams the weights through a reservoir and returns it.
class Chooser {
 public:
  virtual ~Chooser() = default;
  virtual Reservoir pick(std::span<const double> weights) = 0;
};

// The batch as the rounds read it, over the pools of `pools`.
struct ReservoirBatch {
  PreparedPools pools = {};
  std::span<const double> target = {};         // p̂_t(x_j) at t M + j
  std::span<const double> weight_target = {};  // the targets as the MIS weights see them
  std::span<const double> light_pdf = {};      // q of every sampled light path
  std::uint32_t neighbours = 0;                // k = min(N, n - 1)
};

class ReservoirEstimator final : public Estimator {
 public:
  explicit ReservoirEstimator(const ReservoirConfig& config);

  void estimate_batch(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                      std::span<double> estimates) const override;
  bool samples_independent() const override {
    return config_.pool == PoolMode::kFresh && config_.rounds == 0;
  }
  const ReservoirConfig& config() const { return config_; }

  // Samples ctx's camera paths and pools and evaluates the targets (and f of every candidate
  // when `with_contributions`; scratch.contributions then holds f / (p(x) p(y)) at t M + j).
  ReservoirBatch prepare(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                         bool with_contributions) const;

  // visit(probability, terms) for every sequence of choices that decides sample i's estimate:
  // each reservoir sample i's final one depends on (round 0's of samples i .. i + k R, every
  // round's after), each outcome in turn. A term's coefficient weighs f(x_index, y_i) /
  // (p(x_index) p(y_i)), as the resampling step's terms do.
  void enumerate(const ReservoirBatch& batch, std::uint32_t i,
                 const std::function<void(double, std::span<const Term>)>& visit) const;

 private:
  using ChooserFor =
      std::function<Chooser&(std::uint32_t sample, std::uint32_t round, std::uint32_t reservoir)>;

  // The part of a batch whose candidates fit kMaxCandidates (ris; reuse takes a batch whole).
  void estimate_part(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
                     std::span<double> estimates) const;
  // The final reservoirs (K per sample) of samples first, first + 1, .. : all n of them when
  // `whole`, else those that sample `first`'s final one depends on; into out[t K + k].
  void run_rounds(const ReservoirBatch& batch, std::uint32_t first, bool whole,
                  const ChooserFor& chooser_for, std::vector<ReservoirSample>& out) const;
  ReservoirSample initial(const ReservoirBatch& batch, std::uint32_t t, Chooser& chooser,
                          std::vector<double>& weights) const;
  ReservoirSample reuse(const ReservoirBatch& batch, std::uint32_t c,
                        std::span<const ReservoirSample> previous, Chooser& chooser,
                        std::vector<double>& weights) const;
  // Sample t's terms from its final reservoirs.
  void append_terms(const ReservoirBatch& batch, std::uint32_t t,
                    std::span<const ReservoirSample> finals, std::vector<Term>& terms) const;
  // What `pcbench replay` shows of sample t: its first reservoir's choice probabilities over its
  // M candidates, w_j / Σ w, and the pool paths its K final reservoirs hold.
  ResamplingRecord choice_record(const ReservoirBatch& batch, std::uint32_t sample, std::uint32_t t,
                                 std::span<const ReservoirSample> finals) const;

  ReservoirConfig config_;
  ResamplingEstimator pools_;  // samples the pools and evaluates the targets, as the family does
};

}  // namespace pcbench
