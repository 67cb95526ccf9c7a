#include "estimators/resampling_step.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// w > 0 read from the bits: under denormals-are-zero a subnormal w compares equal to 0 although
// the integrand meant a positive importance.
bool positive(double w) {
  return !std::signbit(w) && std::bit_cast<std::uint64_t>(w) != 0;
}

}  // namespace

double ResamplingStep::keep_threshold(std::span<const double> importance) const {
  if (config_.flaw != Flaw::kCullSmall && config_.flaw != Flaw::kRenormaliseKept) {
    return -std::numeric_limits<double>::infinity();
  }
  const double largest =
      importance.empty() ? 0.0 : *std::max_element(importance.begin(), importance.end());
  return config_.severity * largest;
}

void ResamplingStep::build_pmf(const PoolView& pool, std::vector<double>& pmf) const {
  const std::uint32_t m = config_.M;
  pmf.resize(m);
  if (config_.selection != Selection::kImportance) {
    std::fill(pmf.begin(), pmf.end(), 1.0 / m);
    return;
  }
  const std::span<const double> w = pool.importance;
  const double threshold = keep_threshold(w);
  // The importances are scaled by the largest kept one before they are summed: Σ w overflows to
  // inf for weights near DBL_MAX (and then every w / Σ w is 0 and P sums to u, not 1), while the
  // scaled sum lies in [1, M] for any finite weights. Under denormals-are-zero a subnormal largest
  // compares as 0: the pool then counts as all-zero. One pass finds the largest, counts the kept
  // and checks that every weight is finite (this step runs once per camera sample).
  bool finite = true;
  double largest = 0.0;
  std::uint32_t kept = 0;
  for (double wj : w) {
    finite &= std::isfinite(wj);
    if (wj < threshold) continue;
    largest = std::max(largest, wj);
    ++kept;
  }
  if (!finite) {
    std::fill(pmf.begin(), pmf.end(), kNaN);
    return;
  }
  // Multiplying by 1 / largest instead of dividing by it, where that reciprocal is finite (a
  // subnormal largest has none): divisions were most of this step's cost at small M.
  const double inverse = largest > 0.0 ? 1.0 / largest : 0.0;
  const bool by_inverse = std::isfinite(inverse);
  const auto scaled = [&](double wj) { return by_inverse ? wj * inverse : wj / largest; };
  double total = 0.0;
  if (largest > 0.0) {
    for (double wj : w) {
      if (wj >= threshold) total += scaled(wj);
    }
  }
  // P = (1 - u) w / Σ w + u / M; all-zero importances leave P uniform. The negative control
  // kRenormaliseKept spreads the uniform share over the kept candidates only.
  const double u = total > 0.0 ? config_.uniform_mix : 1.0;
  const bool kept_only = config_.flaw == Flaw::kRenormaliseKept;
  const double uniform_share = u / (kept_only ? kept : m);
  const double share_factor = total > 0.0 ? (1.0 - u) / total : 0.0;  // in [(1-u)/M, 1-u]
  for (std::uint32_t j = 0; j < m; ++j) {
    const bool keep = w[j] >= threshold;
    const double share = keep ? scaled(w[j]) * share_factor : 0.0;
    pmf[j] = share + (keep || !kept_only ? uniform_share : 0.0);
    // Without uniform mixing a share can underflow although w_j > 0: a pool whose weights span
    // more than DBL_MAX / DBL_MIN, a share below DBL_MIN flushed to zero (FTZ, as Embree asks),
    // or a subnormal w_j read as 0 (DAZ). P_j = 0 where f may be != 0 would break the proof's
    // support condition, and a subnormal P_j would give the draw the weight 1 / (M K P_j) = inf.
    // The smallest normal number keeps P > 0 wherever w > 0 and every weight finite; the draw
    // stays as rare as the 2^-53 resolution of a uniform lets it be.
    if (keep && pmf[j] < std::numeric_limits<double>::min() && positive(w[j])) {
      pmf[j] = std::numeric_limits<double>::min();
    }
  }
}

void ResamplingStep::weigh(const PoolView& pool, std::span<const double> pmf,
                           std::span<const std::uint32_t> draws, std::vector<Term>& terms) const {
  const std::uint32_t m = config_.M;
  double normaliser = m;
  if (config_.flaw == Flaw::kWrongCount) normaliser = m - config_.severity;
  if (config_.flaw == Flaw::kRenormaliseKept) {
    const double threshold = keep_threshold(pool.importance);
    normaliser = static_cast<double>(std::count_if(pool.importance.begin(), pool.importance.end(),
                                                   [&](double w) { return w >= threshold; }));
  }

  // The P each draw is weighted by: the one it was drawn from, except for kForeignNormaliser.
  double foreign_normaliser = 0.0;
  double foreign_share = 0.0;
  double foreign_uniform = 0.0;
  const bool foreign =
      config_.flaw == Flaw::kForeignNormaliser && config_.selection == Selection::kImportance;
  if (foreign) {
    double total = 0.0;
    for (double w : pool.importance) total += w;
    const double used =
        (1.0 - config_.severity) * total + config_.severity * pool.foreign_importance_total;
    const double u = total > 0.0 ? config_.uniform_mix : 1.0;
    foreign_normaliser = used;
    foreign_share = 1.0 - u;
    foreign_uniform = u / m;
  }
  const auto weight_pmf = [&](std::uint32_t j) {
    // w / Σ first: a tiny Σ must not turn w = 0 into 0 × inf.
    if (!foreign || !(foreign_normaliser > 0.0)) return pmf[j];
    return foreign_share * (pool.importance[j] / foreign_normaliser) + foreign_uniform;
  };

  const std::size_t first = terms.size();
  const double per_draw = 1.0 / (normaliser * static_cast<double>(draws.size()));
  for (std::uint32_t j : draws) {
    terms.push_back({.index = j, .coefficient = per_draw / weight_pmf(j), .pmf = pmf[j]});
  }
  if (config_.flaw != Flaw::kBestDraw || draws.empty()) return;

  // Keep a share of the estimate for the draw that contributed most, weighted as a single draw.
  std::size_t best = first;
  for (std::size_t t = first; t < terms.size(); ++t) {
    const auto value = [&](std::size_t s) {
      return std::fabs(pool.contributions[terms[s].index] * terms[s].coefficient);
    };
    if (value(t) > value(best)) best = t;
  }
  const Term chosen = terms[best];
  for (std::size_t t = first; t < terms.size(); ++t) terms[t].coefficient *= 1.0 - config_.severity;
  terms.push_back({.index = chosen.index,
                   .coefficient = config_.severity / (normaliser * weight_pmf(chosen.index)),
                   .pmf = chosen.pmf});
}

void ResamplingStep::choose(const PoolView& pool, RandomStream& rng, std::vector<double>& pmf,
                            DiscreteSampler& sampler, std::vector<std::uint32_t>& draws,
                            std::vector<Term>& terms) const {
  if (connects_every_path_once()) {
    // Vertex connection (and plain): every path once, P = 1/M, no random numbers; the same
    // coefficients weigh() computes, without its generality.
    const std::uint32_t m = config_.M;
    const double p = 1.0 / m;
    const double coefficient = every_path_coefficient();
    pmf.assign(m, p);
    draws.resize(m);
    for (std::uint32_t j = 0; j < m; ++j) {
      draws[j] = j;
      terms.push_back({.index = j, .coefficient = coefficient, .pmf = p});
    }
    return;
  }
  build_pmf(pool, pmf);
  if (std::isnan(pmf[0])) {
    // No valid P: the estimate is NaN, reported as such rather than drawn from a broken table.
    const std::uint32_t count = config_.scheme == DrawScheme::kEvery ? config_.M : config_.K;
    for (std::uint32_t k = 0; k < count; ++k) terms.push_back({.coefficient = kNaN, .pmf = kNaN});
    return;
  }
  draw_indices(config_.scheme, pmf, config_.K, config_.sampler, sampler, rng, draws);
  weigh(pool, pmf, draws, terms);
}

void ResamplingStep::enumerate(
    const PoolView& pool, const std::function<void(double, std::span<const Term>)>& visit) const {
  std::vector<double> pmf;
  build_pmf(pool, pmf);
  std::vector<Term> terms;
  if (std::isnan(pmf[0])) {
    terms.push_back({.coefficient = kNaN, .pmf = kNaN});
    visit(1.0, terms);
    return;
  }
  enumerate_draws(config_.scheme, pmf, config_.K,
                  [&](double probability, std::span<const std::uint32_t> draws) {
                    terms.clear();
                    weigh(pool, pmf, draws, terms);
                    visit(probability, terms);
                  });
}

}  // namespace pcbench
