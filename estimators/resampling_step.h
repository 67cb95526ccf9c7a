// The resampling step of one camera sample, apart from any integrand: from the pool's
// importances, a PMF P; from P, the draws; from the draws, the weighted terms of the estimate
//     <I> = Σ_terms coefficient × f(x_j, y) / (p(x_j) p(y)),
// which for the honest family is coefficient = 1 / (M K P_j) per draw (the seed's Eq. (2)).
//
// Keeping the step a pure function of the pool's numbers lets the exact check enumerate every
// draw sequence with its probability and compare the expectation with connecting to all paths
// (harness/verify/exact_check.h), for the estimators and for the negative controls alike.
//
// A Flaw is a deliberate bug of a negative control (estimators/negative_controls.h). Each is a
// mistake seen in practice; each breaks one condition of the unbiasedness proof.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "base/discrete_sampler.h"
#include "base/rng.h"
#include "estimators/draw_scheme.h"

namespace pcbench {

enum class Selection { kAll, kUniform, kImportance };

enum class Flaw {
  kNone,
  // Importances below severity × (the pool's largest) are set to 0 before P is built: P = 0
  // where f may not be 0 unless uniform mixing restores it.
  kCullSmall,
  // The estimate is divided by M - severity instead of M (an off-by-one at severity 1).
  kWrongCount,
  // Outcome-selected reuse: a share `severity` of the estimate comes from the one draw that
  // contributed most, weighted as if it had been the only draw.
  kBestDraw,
  // Candidates whose importance is below severity × (the largest) are dropped, P is built over
  // the rest and the estimate divided by the number kept instead of M.
  kRenormaliseKept,
  // Draws follow P built on this pool, but their weight uses a P whose normaliser Σ w mixes in
  // (by `severity`) the total of another, independent pool: P no longer matches the draws.
  kForeignNormaliser,
};

struct StepConfig {
  std::uint32_t M = 1;
  std::uint32_t K = 1;  // draws; M for DrawScheme::kEvery
  Selection selection = Selection::kAll;
  DrawScheme scheme = DrawScheme::kEvery;
  double uniform_mix = 0.1;
  DiscreteSamplerKind sampler = DiscreteSamplerKind::kCdf;
  Flaw flaw = Flaw::kNone;
  double severity = 0.0;
};

// One camera sample's pool, as the step sees it.
struct PoolView {
  std::span<const double> importance = {};  // w(x_j, y) >= 0, j < M (Selection::kImportance)
  // f(x_j, y) / (p(x_j) p(y)) for every j: needed by Flaw::kBestDraw and by the exact check.
  std::span<const double> contributions = {};
  // Σ_j w(x'_j, y) over an independent pool X' (Flaw::kForeignNormaliser).
  double foreign_importance_total = std::numeric_limits<double>::quiet_NaN();
};

struct Term {
  std::uint32_t index = 0;  // into the pool
  double coefficient = 0.0;
  double pmf = 0.0;  // P(index | y, X) of the draw, as logged
};

class ResamplingStep {
 public:
  explicit ResamplingStep(const StepConfig& config) : config_(config) {}

  const StepConfig& config() const { return config_; }
  bool needs_contributions() const { return config_.flaw == Flaw::kBestDraw; }
  // Vertex connection and plain: every path of the pool once with P = 1/M, no random numbers.
  bool connects_every_path_once() const {
    return config_.scheme == DrawScheme::kEvery && config_.flaw == Flaw::kNone &&
           config_.selection != Selection::kImportance;
  }
  // The coefficient of every term when connects_every_path_once(): 1/(M² P) with P = 1/M,
  // computed as choose() computes it, so both paths give the same bits.
  double every_path_coefficient() const {
    const double p = 1.0 / config_.M;
    return 1.0 / (static_cast<double>(config_.M) * static_cast<double>(config_.M)) / p;
  }
  bool needs_foreign_pool() const { return config_.flaw == Flaw::kForeignNormaliser; }

  // P(j | y, X) for j < M, into `pmf`. An importance that is not finite leaves no valid P: every
  // entry is NaN, and so is every estimate made from it.
  void build_pmf(const PoolView& pool, std::vector<double>& pmf) const;

  // Draws (with the random numbers of `rng`, the sample's kResampling stream, when the draws are
  // random) and weighs: appends this sample's terms. `pmf` is scratch (left holding P), `draws`
  // is left holding the draws.
  void choose(const PoolView& pool, RandomStream& rng, std::vector<double>& pmf,
              DiscreteSampler& sampler, std::vector<std::uint32_t>& draws,
              std::vector<Term>& terms) const;

  // The terms of one draw sequence (appended).
  void weigh(const PoolView& pool, std::span<const double> pmf,
             std::span<const std::uint32_t> draws, std::vector<Term>& terms) const;

  // visit(probability, terms) for every draw sequence the step can make on this pool.
  void enumerate(const PoolView& pool,
                 const std::function<void(double, std::span<const Term>)>& visit) const;

 private:
  // Whether candidate j survives the importance threshold of kCullSmall / kRenormaliseKept.
  double keep_threshold(std::span<const double> importance) const;

  StepConfig config_;
};

}  // namespace pcbench
