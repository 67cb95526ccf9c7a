#include "estimators/resampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcbench {

void ResamplingEstimator::choose(const BatchContext& ctx, std::uint32_t i, std::uint32_t start,
                                 EstimatorScratch& scratch) const {
  const std::uint32_t m = config_.M;
  const double uniform_p = 1.0 / static_cast<double>(m);
  if (config_.selection == Selection::kAll) {
    for (std::uint32_t j = 0; j < m; ++j) {
      scratch.pairs.push_back({.light = start + j, .camera = i});
      scratch.draw_pmfs.push_back(uniform_p);
    }
    return;
  }

  StreamId draw_stream = ctx.stream(StreamPurpose::kResampling);
  draw_stream.sample = ctx.first_sample + i;
  RandomStream rng(draw_stream);
  if (config_.selection == Selection::kUniform) {
    for (std::uint32_t k = 0; k < config_.K; ++k) {
      scratch.pairs.push_back({.light = start + rng.uniform_index(m), .camera = i});
      scratch.draw_pmfs.push_back(uniform_p);
    }
    return;
  }

  // P(j | y, X) = (1 - u) w_j / W + u / M; all-zero importances leave P uniform.
  const double* w = scratch.importances.data() + static_cast<std::size_t>(i) * m;
  double total = 0.0;
  for (std::uint32_t j = 0; j < m; ++j) total += w[j];
  scratch.pmf.resize(m);
  if (!std::isfinite(total)) {
    // An infinite or NaN importance (f itself, for importance=f) leaves no valid P: the sample's
    // estimate is not finite, and is reported as such rather than drawn from a broken table.
    std::fill(scratch.pmf.begin(), scratch.pmf.end(), std::numeric_limits<double>::quiet_NaN());
    for (std::uint32_t k = 0; k < config_.K; ++k) {
      scratch.pairs.push_back({.light = start, .camera = i});
      scratch.draw_pmfs.push_back(std::numeric_limits<double>::quiet_NaN());
    }
    return;
  }
  const double u = total > 0.0 ? config_.uniform_mix : 1.0;
  const double scale = total > 0.0 ? (1.0 - u) / total : 0.0;
  for (std::uint32_t j = 0; j < m; ++j) scratch.pmf[j] = w[j] * scale + u * uniform_p;
  scratch.sampler.build(scratch.pmf, config_.sampler);
  for (std::uint32_t k = 0; k < config_.K; ++k) {
    const std::uint32_t j = scratch.sampler.draw(rng);
    scratch.pairs.push_back({.light = start + j, .camera = i});
    scratch.draw_pmfs.push_back(scratch.pmf[j]);
  }
}

void ResamplingEstimator::estimate_batch(const BatchContext& ctx, PathWorkspace& paths,
                                         EstimatorScratch& scratch,
                                         std::span<double> estimates) const {
  // Large pools are handled a few camera samples at a time, so that the candidate pairs of a
  // batch (samples × M) stay within kMaxCandidates. Every random number is keyed by its sample
  // (or batch) index, so the split does not change any estimate; a shared pool is drawn again
  // from its batch's stream and comes out the same.
  const std::uint32_t step = std::max<std::uint32_t>(1, kMaxCandidates / config_.M);
  for (std::uint32_t offset = 0; offset < ctx.sample_count; offset += step) {
    BatchContext part = ctx;
    part.first_sample = ctx.first_sample + offset;
    part.sample_count = std::min(step, ctx.sample_count - offset);
    if (!ctx.magnitudes.empty())
      part.magnitudes = ctx.magnitudes.subspan(offset, part.sample_count);
    estimate_part(part, paths, scratch, estimates.subspan(offset, part.sample_count));
  }
}

void ResamplingEstimator::estimate_part(const BatchContext& ctx, PathWorkspace& paths,
                                        EstimatorScratch& scratch,
                                        std::span<double> estimates) const {
  const std::uint32_t n = ctx.sample_count;
  const std::uint32_t m = config_.M;
  const bool shared = config_.pool == PoolMode::kShared;
  paths.clear();
  paths.sample_paths(PathSide::kCamera, ctx.stream(StreamPurpose::kCameraPath), ctx.first_sample, n,
                     1);
  // A fresh pool per camera sample (pool of sample i = light paths [i M, (i + 1) M)), or one
  // pool for the batch, drawn from the batch's own stream.
  if (shared) {
    paths.sample_paths(PathSide::kLight, ctx.stream(StreamPurpose::kLightPool), ctx.batch_index(),
                       1, m);
  } else {
    paths.sample_paths(PathSide::kLight, ctx.stream(StreamPurpose::kLightPool), ctx.first_sample, n,
                       m);
  }
  const auto pool_start = [&](std::uint32_t i) { return shared ? 0u : i * m; };

  // Importances of every (pool path, camera path) pair, in one call for the batch.
  const bool by_importance = config_.selection == Selection::kImportance;
  if (by_importance) {
    scratch.candidate_pairs.resize(static_cast<std::size_t>(n) * m);
    scratch.importances.resize(scratch.candidate_pairs.size());
    for (std::uint32_t i = 0; i < n; ++i) {
      for (std::uint32_t j = 0; j < m; ++j) {
        scratch.candidate_pairs[static_cast<std::size_t>(i) * m + j] = {.light = pool_start(i) + j,
                                                                        .camera = i};
      }
    }
    switch (config_.importance) {
      case ImportanceSource::kApproximate:
        paths.importance(scratch.candidate_pairs, scratch.importances);
        break;
      case ImportanceSource::kF:
        // f of every candidate is known now: keep it signed, so the chosen ones are not
        // evaluated again below.
        scratch.candidate_values.resize(scratch.candidate_pairs.size());
        paths.connect(scratch.candidate_pairs, scratch.candidate_values);
        for (std::size_t c = 0; c < scratch.importances.size(); ++c) {
          scratch.importances[c] = std::fabs(scratch.candidate_values[c]);
        }
        break;
      case ImportanceSource::kUniform:
        std::fill(scratch.importances.begin(), scratch.importances.end(), 1.0);
        break;
    }
    if (config_.importance != ImportanceSource::kUniform) {
      ctx.counters->importance_evaluations += scratch.candidate_pairs.size();
    }
  }

  // Choose the connections of every camera sample, then evaluate them in one call.
  scratch.pairs.clear();
  scratch.draw_pmfs.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::size_t first_draw = scratch.pairs.size();
    choose(ctx, i, pool_start(i), scratch);
    if (ctx.log != nullptr) {
      ResamplingRecord record{.sample = ctx.first_sample + i};
      if (by_importance) {
        record.pmf = scratch.pmf;
      } else {
        record.pmf.assign(m, 1.0 / static_cast<double>(m));
      }
      for (std::size_t d = first_draw; d < scratch.pairs.size(); ++d) {
        record.draws.push_back(scratch.pairs[d].light - pool_start(i));
      }
      ctx.log->push_back(std::move(record));
    }
  }
  scratch.values.resize(scratch.pairs.size());
  if (by_importance && config_.importance == ImportanceSource::kF) {
    for (std::size_t d = 0; d < scratch.pairs.size(); ++d) {
      const std::size_t i = scratch.pairs[d].camera;
      const std::size_t j = scratch.pairs[d].light - pool_start(scratch.pairs[d].camera);
      scratch.values[d] = scratch.candidate_values[i * m + j];
    }
  } else {
    paths.connect(scratch.pairs, scratch.values);
  }

  // Eq. (2): average of f / (p(x) p(y) P) over the K connections, divided by M.
  const std::span<const double> p_x = paths.pdfs(PathSide::kLight);
  const std::span<const double> p_y = paths.pdfs(PathSide::kCamera);
  const std::size_t per_sample = scratch.pairs.size() / n;
  const double normalisation = 1.0 / (static_cast<double>(m) * static_cast<double>(per_sample));
  const bool with_magnitudes = !ctx.magnitudes.empty();
  for (std::uint32_t i = 0; i < n; ++i) {
    double sum = 0.0;
    double magnitude = 0.0;
    for (std::size_t d = i * per_sample; d < (i + 1) * per_sample; ++d) {
      const double f = scratch.values[d];
      // f = 0 contributes 0 whatever P is; f != 0 with P = 0 is a bias made visible (inf); a
      // NaN P (no valid distribution) makes the sample NaN whatever f is.
      if (f == 0.0 && !std::isnan(scratch.draw_pmfs[d])) continue;
      const double weight = 1.0 / (p_x[scratch.pairs[d].light] * p_y[i] * scratch.draw_pmfs[d]);
      sum += f * weight;
      magnitude += std::fabs(f) * weight;
    }
    estimates[i] = sum * normalisation;
    if (with_magnitudes) ctx.magnitudes[i] = magnitude * normalisation;
  }
  ctx.counters->camera_paths += n;
  ctx.counters->light_paths += shared ? m : static_cast<std::uint64_t>(n) * m;
  ctx.counters->connections += scratch.pairs.size();
}

}  // namespace pcbench
