#include "estimators/reservoir_estimator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Candidate pairs (camera samples × pool paths) of one part of a batch, as the family bounds them.
constexpr std::uint32_t kMaxCandidates = 1u << 20;

// A run's choices: each a reservoir streamed once over the weights with the uniforms of its own
// stream.
class SamplingChooser final : public Chooser {
 public:
  void reset(const StreamId& id) { rng_ = RandomStream(id); }
  Reservoir pick(std::span<const double> weights) override {
    Reservoir reservoir;
    for (std::size_t j = 0; j < weights.size(); ++j) {
      reservoir.offer(static_cast<std::uint32_t>(j), weights[j], rng_);
    }
    return reservoir;
  }

 private:
  RandomStream rng_{StreamId{}};
};

// The exact check's choices: an odometer over every outcome of every choice, in the order the
// estimate makes them. A later choice's weights depend on the earlier outcomes, so advancing a
// choice forgets every choice after it, and the next pass decides them anew.
class EnumeratingChooser final : public Chooser {
 public:
  Reservoir pick(std::span<const double> weights) override {
    std::vector<double> probabilities;
    Reservoir reservoir = reservoir_probabilities(weights, probabilities);
    if (next_ == choices_.size()) {
      choices_.push_back({.probabilities = probabilities, .outcome = Reservoir::kEmpty});
      advance_choice(choices_.back());
    }
    const Choice& choice = choices_[next_++];
    if (choice.outcome != Reservoir::kEmpty) {
      reservoir.keep(choice.outcome);
      probability_ *= choice.probabilities[choice.outcome];
    }
    return reservoir;
  }
  double probability() const { return probability_; }
  // The next sequence of outcomes; false when every one has been visited.
  bool advance() {
    next_ = 0;
    probability_ = 1.0;
    while (!choices_.empty()) {
      if (advance_choice(choices_.back())) return true;
      choices_.pop_back();
    }
    return false;
  }

 private:
  struct Choice {
    std::vector<double> probabilities;
    std::uint32_t outcome;  // kEmpty before the first; stays kEmpty when nothing can be kept
  };
  // Moves to the next outcome of positive probability; false when there is none (the first
  // call on a choice of all-zero weights leaves it empty and returns false).
  static bool advance_choice(Choice& choice) {
    const auto size = static_cast<std::uint32_t>(choice.probabilities.size());
    std::uint32_t j = choice.outcome == Reservoir::kEmpty ? 0 : choice.outcome + 1;
    for (; j < size; ++j) {
      if (choice.probabilities[j] > 0.0) {
        choice.outcome = j;
        return true;
      }
    }
    return false;
  }

  std::vector<Choice> choices_;
  std::size_t next_ = 0;
  double probability_ = 1.0;
};

}  // namespace

ReservoirEstimator::ReservoirEstimator(const ReservoirConfig& config)
    : config_(config),
      pools_(ResamplingConfig{.step = {.M = config.M, .selection = Selection::kImportance},
                              .pool = config.pool,
                              .importance = config.target}) {}

ReservoirBatch ReservoirEstimator::prepare(const BatchContext& ctx, PathWorkspace& paths,
                                           EstimatorScratch& scratch,
                                           bool with_contributions) const {
  ReservoirBatch batch{.pools = pools_.prepare(ctx, paths, scratch, with_contributions)};
  const std::uint32_t n = batch.pools.samples;
  batch.target = scratch.importances;
  batch.weight_target = scratch.importances;
  batch.light_pdf = paths.pdfs(PathSide::kLight);
  batch.neighbours = std::min(config_.neighbours, n - 1);
  const std::uint64_t candidates = std::uint64_t{n} * config_.M;
  if (ctx.counters != nullptr && config_.target != ImportanceSource::kUniform) {
    ctx.counters->importance_evaluations += candidates;
  }
  if (config_.unshadowed_share > 0.0) {
    // The control's weight targets: the neighbours' p̂ blended with the approximation, which
    // sees no visibility (reuse reads the canonical sample's own p̂ from `target`).
    std::vector<double>& blended = scratch.weight_targets;
    blended.resize(candidates);
    paths.importance(scratch.candidate_pairs, blended);
    const double s = config_.unshadowed_share;
    for (std::size_t c = 0; c < candidates; ++c) {
      blended[c] = (1.0 - s) * scratch.importances[c] + s * blended[c];
    }
    batch.weight_target = blended;
    if (ctx.counters != nullptr) ctx.counters->importance_evaluations += candidates;
  }
  return batch;
}

ReservoirSample ReservoirEstimator::initial(const ReservoirBatch& batch, std::uint32_t t,
                                            Chooser& chooser, std::vector<double>& weights) const {
  const std::uint32_t m = config_.M;
  const std::span<const double> target = batch.target.subspan(std::size_t{t} * m, m);
  const std::span<const double> q = batch.light_pdf.subspan(batch.pools.pool_start(t), m);
  weights.resize(m);
  for (std::uint32_t j = 0; j < m; ++j) weights[j] = target[j] / q[j];  // w = p̂ / q
  const Reservoir reservoir = chooser.pick(weights);
  if (!std::isfinite(reservoir.weight_sum())) return {.index = 0, .W = kNaN};
  if (reservoir.empty()) return {};
  const std::uint32_t y = reservoir.kept();
  return {.index = y, .W = reservoir.weight_sum() / (m * target[y])};
}

ReservoirSample ReservoirEstimator::reuse(const ReservoirBatch& batch, std::uint32_t c,
                                          std::span<const ReservoirSample> previous,
                                          Chooser& chooser, std::vector<double>& weights) const {
  const std::uint32_t n = batch.pools.samples;
  const std::uint32_t m = config_.M;
  const std::uint32_t k = batch.neighbours;
  const auto source = [&](std::uint32_t a) { return (c + a) % n; };
  const auto target_of = [&](std::uint32_t t, std::uint32_t j) {
    return batch.target[std::size_t{t} * m + j];
  };
  std::array<double, kMaxReuseNeighbours + 1> storage;
  const std::span<double> targets(storage.data(), k + 1);  // every source's target at one sample
  weights.assign(k + 1, 0.0);
  for (std::uint32_t a = 0; a <= k; ++a) {
    const ReservoirSample& in = previous[source(a)];
    if (std::isnan(in.W)) return {.index = 0, .W = kNaN};
    if (in.index == Reservoir::kEmpty || !(in.W > 0.0)) continue;
    // The canonical sample's own target, the neighbours' as the weights see them.
    targets[0] = target_of(c, in.index);
    for (std::uint32_t b = 1; b <= k; ++b) {
      targets[b] = batch.weight_target[std::size_t{source(b)} * m + in.index];
    }
    weights[a] = reuse_mis_weight(config_.weighting, targets, a) * target_of(c, in.index) * in.W;
  }
  const Reservoir reservoir = chooser.pick(weights);
  if (!std::isfinite(reservoir.weight_sum())) return {.index = 0, .W = kNaN};
  if (reservoir.empty()) return {};
  const std::uint32_t y = previous[source(reservoir.kept())].index;
  return {.index = y, .W = reservoir.weight_sum() / target_of(c, y)};
}

void ReservoirEstimator::run_rounds(const ReservoirBatch& batch, std::uint32_t first, bool whole,
                                    const ChooserFor& chooser_for,
                                    std::vector<ReservoirSample>& out) const {
  const std::uint32_t n = batch.pools.samples;
  const std::uint32_t K = config_.K;
  const std::uint32_t rounds = config_.rounds;
  // Samples first .. first + extent(r) - 1 (mod n) after round r: sample `first` after the last
  // round reads k sources a round, so round r needs k (rounds - r) samples after it.
  const auto extent = [&](std::uint32_t r) {
    return whole ? n : std::min(n, 1 + batch.neighbours * (rounds - r));
  };
  std::vector<double> weights;
  out.assign(std::size_t{n} * K, {});
  for (std::uint32_t e = 0; e < extent(0); ++e) {
    const std::uint32_t t = (first + e) % n;
    for (std::uint32_t k = 0; k < K; ++k) {
      out[std::size_t{t} * K + k] = initial(batch, t, chooser_for(t, 0, k), weights);
    }
  }
  std::vector<ReservoirSample> next;
  for (std::uint32_t r = 1; r <= rounds; ++r) {
    next.assign(n, {});
    for (std::uint32_t e = 0; e < extent(r); ++e) {
      const std::uint32_t t = (first + e) % n;
      next[t] = reuse(batch, t, out, chooser_for(t, r, 0), weights);
    }
    out.swap(next);
  }
}

void ReservoirEstimator::append_terms(const ReservoirBatch& batch, std::uint32_t t,
                                      std::span<const ReservoirSample> finals,
                                      std::vector<Term>& terms) const {
  const double share = 1.0 / static_cast<double>(finals.size());
  for (const ReservoirSample& s : finals) {
    if (std::isnan(s.W)) {
      terms.push_back({.index = 0, .coefficient = kNaN, .pmf = kNaN});
    } else if (s.index != Reservoir::kEmpty) {
      // f W / p(y) as a term of f / (q p(y)): the coefficient is W q.
      const double q = batch.light_pdf[batch.pools.pool_start(t) + s.index];
      terms.push_back({.index = s.index, .coefficient = share * s.W * q, .pmf = kNaN});
    }
  }
}

ResamplingRecord ReservoirEstimator::choice_record(const ReservoirBatch& batch,
                                                   std::uint32_t sample, std::uint32_t t,
                                                   std::span<const ReservoirSample> finals) const {
  const std::uint32_t m = config_.M;
  const std::span<const double> target = batch.target.subspan(std::size_t{t} * m, m);
  const std::span<const double> q = batch.light_pdf.subspan(batch.pools.pool_start(t), m);
  ResamplingRecord record{.sample = sample, .pmf = std::vector<double>(m), .draws = {}};
  double sum = 0.0;
  for (std::uint32_t j = 0; j < m; ++j) sum += record.pmf[j] = target[j] / q[j];
  for (double& p : record.pmf) p = sum > 0.0 ? p / sum : 0.0;
  for (const ReservoirSample& s : finals) {
    if (s.index != Reservoir::kEmpty && !std::isnan(s.W)) record.draws.push_back(s.index);
  }
  return record;
}

void ReservoirEstimator::enumerate(
    const ReservoirBatch& batch, std::uint32_t i,
    const std::function<void(double, std::span<const Term>)>& visit) const {
  EnumeratingChooser chooser;
  std::vector<ReservoirSample> finals;
  std::vector<Term> terms;
  const ChooserFor chooser_for = [&](std::uint32_t, std::uint32_t, std::uint32_t) -> Chooser& {
    return chooser;
  };
  do {
    run_rounds(batch, i, false, chooser_for, finals);
    terms.clear();
    append_terms(batch, i, std::span(finals).subspan(std::size_t{i} * config_.K, config_.K), terms);
    visit(chooser.probability(), terms);
  } while (chooser.advance());
}

void ReservoirEstimator::estimate_batch(const BatchContext& ctx, PathWorkspace& paths,
                                        EstimatorScratch& scratch,
                                        std::span<double> estimates) const {
  // Reuse reads the whole batch (its M is bounded so that the batch fits); without reuse each
  // sample is on its own and a large pool is taken a few samples at a time, as the family does.
  const std::uint32_t step = config_.rounds > 0
                                 ? ctx.sample_count
                                 : std::max<std::uint32_t>(1, kMaxCandidates / config_.M);
  for (std::uint32_t offset = 0; offset < ctx.sample_count; offset += step) {
    BatchContext part = ctx;
    part.first_sample = ctx.first_sample + offset;
    part.sample_count = std::min(step, ctx.sample_count - offset);
    if (!ctx.magnitudes.empty()) {
      part.magnitudes = ctx.magnitudes.subspan(offset, part.sample_count);
    }
    estimate_part(part, paths, scratch, estimates.subspan(offset, part.sample_count));
  }
}

void ReservoirEstimator::estimate_part(const BatchContext& ctx, PathWorkspace& paths,
                                       EstimatorScratch& scratch,
                                       std::span<double> estimates) const {
  const ReservoirBatch batch = prepare(ctx, paths, scratch, false);
  const std::uint32_t n = batch.pools.samples;
  const std::uint32_t K = config_.K;
  SamplingChooser sampling;
  const ChooserFor chooser_for = [&](std::uint32_t t, std::uint32_t round,
                                     std::uint32_t k) -> Chooser& {
    StreamId id =
        ctx.stream(round == 0 ? StreamPurpose::kResampling : StreamPurpose::kEstimatorAux);
    id.sample = ctx.first_sample + t;
    id.path = round == 0 ? k : round;
    sampling.reset(id);
    return sampling;
  };
  std::vector<ReservoirSample> finals;
  run_rounds(batch, 0, true, chooser_for, finals);

  scratch.terms.clear();
  scratch.term_offsets.assign(1, 0);
  scratch.pairs.clear();
  for (std::uint32_t t = 0; t < n; ++t) {
    const std::span<const ReservoirSample> own = std::span(finals).subspan(std::size_t{t} * K, K);
    append_terms(batch, t, own, scratch.terms);
    close_sample_terms(scratch, batch.pools.pool_start(t), t);
    if (ctx.log != nullptr) ctx.log->push_back(choice_record(batch, ctx.first_sample + t, t, own));
  }
  sum_terms(ctx, paths, scratch, config_.M, estimates);
}

}  // namespace pcbench
