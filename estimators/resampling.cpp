#include "estimators/resampling.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pcbench {
namespace {

// The adversarial importance: positive everywhere (so the estimator stays unbiased) but largest
// where the approximation says f is smallest.
void make_adversarial(std::span<double> w) {
  const double largest = *std::max_element(w.begin(), w.end());
  for (double& v : w) v = 1.0 / (0.01 + (largest > 0.0 ? v / largest : 0.0));
}

}  // namespace

void ResamplingEstimator::estimate_batch(const BatchContext& ctx, PathWorkspace& paths,
                                         EstimatorScratch& scratch,
                                         std::span<double> estimates) const {
  // Large pools are handled a few camera samples at a time, so that the candidate pairs of a
  // batch (samples × M) stay within kMaxCandidates. Every random number is keyed by its sample
  // (or batch) index, so the split does not change any estimate; a shared pool is drawn again
  // from its batch's stream and comes out the same.
  const std::uint32_t step = std::max<std::uint32_t>(1, kMaxCandidates / config_.step.M);
  for (std::uint32_t offset = 0; offset < ctx.sample_count; offset += step) {
    BatchContext part = ctx;
    part.first_sample = ctx.first_sample + offset;
    part.sample_count = std::min(step, ctx.sample_count - offset);
    if (!ctx.magnitudes.empty())
      part.magnitudes = ctx.magnitudes.subspan(offset, part.sample_count);
    estimate_part(part, paths, scratch, estimates.subspan(offset, part.sample_count));
  }
}

bool ResamplingEstimator::tally_batch(const BatchContext& ctx, PathWorkspace& paths, Tally& tally,
                                      CompensatedSum& magnitudes) const {
  if (!step_.connects_every_path_once() || config_.pool != PoolMode::kFresh ||
      step_.needs_foreign_pool() || ctx.log != nullptr) {
    return false;
  }
  const std::uint32_t m = config_.step.M;
  if (!paths.tally_every_path(ctx.stream(StreamPurpose::kLightPool),
                              ctx.stream(StreamPurpose::kCameraPath), ctx.first_sample,
                              ctx.sample_count, m, step_.every_path_coefficient(), tally,
                              magnitudes)) {
    return false;
  }
  // What prepare() and estimate_every_path() count.
  const std::uint64_t candidates = std::uint64_t{ctx.sample_count} * m;
  if (ctx.counters != nullptr) {
    ctx.counters->camera_paths += ctx.sample_count;
    ctx.counters->light_paths += candidates;
    ctx.counters->connections += candidates;
  }
  return true;
}

PreparedPools ResamplingEstimator::prepare(const BatchContext& ctx, PathWorkspace& paths,
                                           EstimatorScratch& scratch,
                                           bool with_contributions) const {
  const PreparedPools pools{.samples = ctx.sample_count,
                            .M = config_.step.M,
                            .shared = config_.pool == PoolMode::kShared};
  const std::uint32_t n = pools.samples;
  const std::uint32_t m = pools.M;
  paths.clear();
  paths.sample_paths(PathSide::kCamera, ctx.stream(StreamPurpose::kCameraPath), ctx.first_sample, n,
                     1);
  // A fresh pool per camera sample (pool of sample i = light paths [i M, (i + 1) M)), or one
  // pool for the batch, drawn from the batch's own stream. A control that needs an independent
  // second pool gets it from the auxiliary stream, laid out the same way after the first.
  const auto sample_pools = [&](StreamPurpose purpose) {
    if (pools.shared) {
      paths.sample_paths(PathSide::kLight, ctx.stream(purpose), ctx.batch_index(), 1, m);
    } else {
      paths.sample_paths(PathSide::kLight, ctx.stream(purpose), ctx.first_sample, n, m);
    }
  };
  sample_pools(StreamPurpose::kLightPool);
  if (step_.needs_foreign_pool()) sample_pools(StreamPurpose::kEstimatorAux);

  const std::size_t candidates = static_cast<std::size_t>(n) * m;
  scratch.candidate_pairs.resize(candidates);
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = 0; j < m; ++j) {
      scratch.candidate_pairs[static_cast<std::size_t>(i) * m + j] = {
          .light = pools.pool_start(i) + j, .camera = i};
    }
  }
  scratch.candidate_values.clear();
  scratch.contributions.clear();
  if (with_contributions || step_.needs_contributions() ||
      (config_.step.selection == Selection::kImportance &&
       config_.importance == ImportanceSource::kF)) {
    scratch.candidate_values.resize(candidates);
    paths.connect(scratch.candidate_pairs, scratch.candidate_values);
    const std::span<const double> p_x = paths.pdfs(PathSide::kLight);
    const std::span<const double> p_y = paths.pdfs(PathSide::kCamera);
    scratch.contributions.resize(candidates);
    for (std::size_t c = 0; c < candidates; ++c) {
      const PathPair pair = scratch.candidate_pairs[c];
      scratch.contributions[c] = scratch.candidate_values[c] / (p_x[pair.light] * p_y[pair.camera]);
    }
  }
  if (config_.step.selection == Selection::kImportance) evaluate_importance(pools, paths, scratch);
  if (ctx.counters != nullptr) {
    ctx.counters->camera_paths += n;
    ctx.counters->light_paths += pools.shared ? m : candidates;
  }
  return pools;
}

void ResamplingEstimator::evaluate_importance(const PreparedPools& pools, PathWorkspace& paths,
                                              EstimatorScratch& scratch) const {
  const std::uint32_t n = pools.samples;
  const std::uint32_t m = pools.M;
  const std::size_t candidates = static_cast<std::size_t>(n) * m;
  const bool foreign = step_.needs_foreign_pool();
  const std::uint32_t width = foreign ? 2 * m : m;
  const std::size_t pairs = static_cast<std::size_t>(n) * width;
  scratch.importances.resize(pairs);

  if (config_.importance == ImportanceSource::kUniform) {
    std::fill(scratch.importances.begin(), scratch.importances.end(), 1.0);
    return;
  }
  if (config_.importance == ImportanceSource::kF && !foreign) {
    // f of every candidate is known already: |f| is the importance, and the chosen connections
    // reuse f instead of evaluating it again.
    for (std::size_t c = 0; c < candidates; ++c) {
      scratch.importances[c] = std::fabs(scratch.candidate_values[c]);
    }
    return;
  }

  // Sample i's candidates, then (for the foreign pool) the same count from the second pool,
  // seen from camera path i, or from its cache point (camera path n + i).
  const bool cached = config_.importance == ImportanceSource::kCached;
  if (cached) paths.add_cache_points(config_.cache_cells);
  scratch.importance_pairs.resize(pairs);
  const std::uint32_t second_pool = pools.shared ? m : static_cast<std::uint32_t>(candidates);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t camera = cached ? n + i : i;
    for (std::uint32_t j = 0; j < width; ++j) {
      const std::uint32_t light =
          j < m ? pools.pool_start(i) + j : second_pool + pools.pool_start(i) + (j - m);
      scratch.importance_pairs[static_cast<std::size_t>(i) * width + j] = {.light = light,
                                                                           .camera = camera};
    }
  }
  switch (config_.importance) {
    case ImportanceSource::kF:
    case ImportanceSource::kCached:
      paths.connect(scratch.importance_pairs, scratch.importances);
      for (double& w : scratch.importances) w = std::fabs(w);
      break;
    case ImportanceSource::kApproximate:
    case ImportanceSource::kAdversarial:
      paths.importance(scratch.importance_pairs, scratch.importances);
      break;
    case ImportanceSource::kUniform:
      break;
  }
  if (config_.importance == ImportanceSource::kAdversarial) {
    for (std::size_t first = 0; first < pairs; first += m) {
      make_adversarial(std::span<double>(scratch.importances).subspan(first, m));
    }
  }
}

PoolView ResamplingEstimator::pool_view(const PreparedPools& pools, const EstimatorScratch& scratch,
                                        std::uint32_t i) const {
  const std::uint32_t m = pools.M;
  PoolView view;
  if (!scratch.contributions.empty()) {
    view.contributions =
        std::span<const double>(scratch.contributions).subspan(std::size_t{i} * m, m);
  }
  if (config_.step.selection != Selection::kImportance) return view;
  const bool foreign = step_.needs_foreign_pool();
  const std::size_t width = foreign ? 2 * m : m;
  const std::span<const double> all(scratch.importances);
  view.importance = all.subspan(i * width, m);
  if (foreign) {
    const std::span<const double> other = all.subspan(i * width + m, m);
    view.foreign_importance_total = std::accumulate(other.begin(), other.end(), 0.0);
  }
  return view;
}

// Plain and vertex connection, the hot path of the cheapest runs: every candidate pair of
// prepare() is a connection with the same coefficient, so there is nothing to choose, and the
// sums are those of the general path below term by term (the same operations: the same bits).
void ResamplingEstimator::estimate_every_path(const BatchContext& ctx, PathWorkspace& paths,
                                              EstimatorScratch& scratch, const PreparedPools& pools,
                                              std::span<double> estimates) const {
  const std::uint32_t m = pools.M;
  const std::span<const PathPair> pairs = scratch.candidate_pairs;
  if (scratch.candidate_values.empty()) {
    scratch.values.resize(pairs.size());
    paths.connect(pairs, scratch.values);
  }
  const std::span<const double> values = scratch.candidate_values.empty()
                                             ? std::span<const double>(scratch.values)
                                             : std::span<const double>(scratch.candidate_values);
  const std::span<const double> p_x = paths.pdfs(PathSide::kLight);
  const std::span<const double> p_y = paths.pdfs(PathSide::kCamera);
  const double coefficient = step_.every_path_coefficient();
  const bool with_magnitudes = !ctx.magnitudes.empty();
  for (std::uint32_t i = 0; i < pools.samples; ++i) {
    double sum = 0.0;
    double magnitude = 0.0;
    for (std::size_t d = static_cast<std::size_t>(i) * m; d < static_cast<std::size_t>(i + 1) * m;
         ++d) {
      const double f = values[d];
      if (f == 0.0) continue;
      add_connection_term(f, coefficient, p_x[pairs[d].light], p_y[i], sum, magnitude);
    }
    estimates[i] = sum;
    if (with_magnitudes) ctx.magnitudes[i] = magnitude;
  }
  ctx.counters->connections += pairs.size();
}

void ResamplingEstimator::estimate_part(const BatchContext& ctx, PathWorkspace& paths,
                                        EstimatorScratch& scratch,
                                        std::span<double> estimates) const {
  const PreparedPools pools = prepare(ctx, paths, scratch, false);
  const std::uint32_t n = pools.samples;
  const std::uint32_t m = pools.M;
  if (config_.step.selection == Selection::kImportance &&
      config_.importance != ImportanceSource::kUniform) {
    ctx.counters->importance_evaluations += static_cast<std::uint64_t>(n) * m;
  }

  if (step_.connects_every_path_once() && ctx.log == nullptr) {
    estimate_every_path(ctx, paths, scratch, pools, estimates);
    return;
  }

  // Choose and weigh the connections of every camera sample, then evaluate them in one call.
  scratch.terms.clear();
  scratch.term_offsets.assign(1, 0);
  scratch.pairs.clear();
  SampleStreams draw_streams(ctx.stream(StreamPurpose::kResampling), ctx.first_sample, n);
  for (std::uint32_t i = 0; i < n; ++i) {
    RandomStream draw_stream = draw_streams.next();
    step_.choose(pool_view(pools, scratch, i), draw_stream, scratch.pmf, scratch.sampler,
                 scratch.draws, scratch.terms);
    close_sample_terms(scratch, pools.pool_start(i), i);
    if (ctx.log != nullptr) {
      ctx.log->push_back({.sample = ctx.first_sample + i,
                          .pmf = scratch.pmf,
                          .draws = std::vector<std::uint32_t>(scratch.draws)});
    }
  }
  sum_terms(ctx, paths, scratch, m, estimates);
}

void close_sample_terms(EstimatorScratch& scratch, std::uint32_t pool_start, std::uint32_t i) {
  for (std::size_t t = scratch.term_offsets.back(); t < scratch.terms.size(); ++t) {
    scratch.pairs.push_back({.light = pool_start + scratch.terms[t].index, .camera = i});
  }
  scratch.term_offsets.push_back(scratch.terms.size());
}

void sum_terms(const BatchContext& ctx, PathWorkspace& paths, EstimatorScratch& scratch,
               std::uint32_t m, std::span<double> estimates) {
  const auto n = static_cast<std::uint32_t>(scratch.term_offsets.size() - 1);
  scratch.values.resize(scratch.pairs.size());
  if (!scratch.candidate_values.empty()) {
    for (std::size_t d = 0; d < scratch.pairs.size(); ++d) {
      const std::size_t i = scratch.pairs[d].camera;
      scratch.values[d] = scratch.candidate_values[i * m + scratch.terms[d].index];
    }
  } else {
    paths.connect(scratch.pairs, scratch.values);
  }

  // Σ coefficient × f / (p(x) p(y)) over each sample's terms.
  const std::span<const double> p_x = paths.pdfs(PathSide::kLight);
  const std::span<const double> p_y = paths.pdfs(PathSide::kCamera);
  const bool with_magnitudes = !ctx.magnitudes.empty();
  for (std::uint32_t i = 0; i < n; ++i) {
    double sum = 0.0;
    double magnitude = 0.0;
    for (std::size_t d = scratch.term_offsets[i]; d < scratch.term_offsets[i + 1]; ++d) {
      const double f = scratch.values[d];
      const double coefficient = scratch.terms[d].coefficient;
      // f = 0 contributes 0 whatever its weight; a NaN weight (no valid P) makes the sample NaN
      // whatever f is.
      if (f == 0.0 && !std::isnan(coefficient)) continue;
      add_connection_term(f, coefficient, p_x[scratch.pairs[d].light], p_y[i], sum, magnitude);
    }
    estimates[i] = sum;
    if (with_magnitudes) ctx.magnitudes[i] = magnitude;
  }
  ctx.counters->connections += scratch.pairs.size();
}

}  // namespace pcbench
