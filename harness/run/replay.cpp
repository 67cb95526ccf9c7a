#include "harness/run/replay.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>

#include "base/errors.h"
#include "harness/run/saved_run.h"

namespace pcbench {
namespace {

// An argument as the shell reads it back: as it is when it holds only harmless characters,
// otherwise in single quotes (a quote inside written '\'').
std::string shell_quoted(const std::string& argument) {
  const bool plain = !argument.empty() && argument.find_first_not_of(
                                              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789_-+=.,:/@%") == std::string::npos;
  if (plain) return argument;
  std::string out = "'";
  for (char c : argument) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

std::string stream_id(const RunPlan& plan) {
  return fmt::format("{:016x}", plan.id_hash);
}

// One batch of the run's replicate, evaluated with the run's streams (and optionally logged).
struct BatchEvaluation {
  std::vector<double> estimates;
  std::vector<ResamplingRecord> log;
};

BatchEvaluation evaluate(const RunPlan& plan, std::uint64_t seed, std::uint32_t replicate,
                         std::uint64_t first, std::uint32_t count, PathWorkspace& paths) {
  BatchEvaluation out;
  Counters counters;
  EstimatorScratch scratch;
  BatchContext ctx{.key = run_key(seed, plan.stream_hash),
                   .replicate = replicate,
                   .first_sample = static_cast<std::uint32_t>(first),
                   .sample_count = count,
                   .counters = &counters,
                   .log = &out.log};
  out.estimates.resize(count);
  plan.made_estimator->estimate_batch(ctx, paths, scratch, out.estimates);
  return out;
}

bool same_bits_or_both_nan(double a, double b) {
  if (std::isnan(a) && std::isnan(b)) return true;
  return std::memcmp(&a, &b, sizeof a) == 0;
}

std::string numbers_text(const auto& values) {
  std::string out = "[";
  for (const auto& v : values) out += (out.size() > 1 ? ", " : "") + fmt::format("{}", v);
  return out + "]";
}

nlohmann::ordered_json path_json(const ReplayedPath& path) {
  nlohmann::ordered_json coordinates = nlohmann::ordered_json::array();
  for (double c : path.coordinates) coordinates.push_back(exact_number(c));
  return {{"pdf", exact_number(path.pdf)}, {"coordinates", coordinates}};
}

// The pool lines printed as text; --json prints every one.
constexpr std::size_t kPrintedPoolPaths = 16;

void print_text(const RunPlan& plan, std::uint64_t seed, std::uint32_t replicate,
                std::uint64_t sample, const ReplayedSample& r, std::ostream& out) {
  out << fmt::format(
      "replay of run {} ({} × {}): seed {}, replicate {}, sample {} (batch of samples {}..{})\n",
      stream_id(plan), plan.estimator->name, plan.integrand->name, seed, replicate, sample,
      r.batch_first, r.batch_first + r.batch_count - 1);
  out << fmt::format("estimate: {}\n", r.estimate);
  if (!same_bits_or_both_nan(r.estimate, r.estimate_alone)) {
    out << fmt::format(
        "warning: evaluated alone the sample gives {} (the details below are from that "
        "evaluation): the estimator's result depends on its batch\n",
        r.estimate_alone);
  }
  out << fmt::format("camera path y: p(y) = {}, y = {}\n", r.camera.pdf,
                     numbers_text(r.camera.coordinates));
  out << fmt::format("pool X: {} light paths\n", r.pool.size());
  for (std::size_t j = 0; j < r.pool.size() && j < kPrintedPoolPaths; ++j) {
    const ReplayedCandidate& c = r.pool[j];
    out << fmt::format("  x[{}]: p(x) = {}, x = {}, f(x, y) = {}, f / (p(x) p(y)) = {}\n", j,
                       c.path.pdf, numbers_text(c.path.coordinates), c.f, c.contribution);
  }
  if (r.pool.size() > kPrintedPoolPaths) {
    out << fmt::format("  ... {} more (--json prints every one)\n",
                       r.pool.size() - kPrintedPoolPaths);
  }
  out << fmt::format("P(j | y, X): {}\n", numbers_text(r.pmf));
  out << fmt::format("draws: {}\n", numbers_text(r.draws));
}

void print_json(const RunPlan& plan, std::uint64_t seed, std::uint32_t replicate,
                std::uint64_t sample, const ReplayedSample& r, std::ostream& out) {
  nlohmann::ordered_json pool = nlohmann::ordered_json::array();
  for (const ReplayedCandidate& c : r.pool) {
    nlohmann::ordered_json entry = path_json(c.path);
    entry["f"] = exact_number(c.f);
    entry["contribution"] = exact_number(c.contribution);
    pool.push_back(entry);
  }
  nlohmann::ordered_json pmf = nlohmann::ordered_json::array();
  for (double p : r.pmf) pmf.push_back(exact_number(p));
  const nlohmann::ordered_json json{{"run_id", stream_id(plan)},
                                    {"estimator", plan.estimator->name},
                                    {"integrand", plan.integrand->name},
                                    {"seed", seed},
                                    {"replicate", replicate},
                                    {"sample", sample},
                                    {"batch_first", r.batch_first},
                                    {"batch_count", r.batch_count},
                                    {"estimate", exact_number(r.estimate)},
                                    {"estimate_alone", exact_number(r.estimate_alone)},
                                    {"camera", path_json(r.camera)},
                                    {"pool", pool},
                                    {"pmf", pmf},
                                    {"draws", r.draws}};
  out << json.dump(2) << "\n";
}

}  // namespace

std::optional<std::string> replay_command(const RunPlan& plan, const NonfiniteLocation& where) {
  if (plan.render) return std::nullopt;
  std::string command =
      fmt::format("pcbench replay -e {} -i {}", shell_quoted(plan.estimator->name),
                  shell_quoted(plan.integrand->name));
  for (const ResolvedParams* params : {&plan.estimator_params, &plan.integrand_params}) {
    for (const auto& [key, value] : params->values()) {
      command += " -p " + shell_quoted(key + "=" + to_text(value));
    }
  }
  return command + fmt::format(" -n {} -r {} --seed {} --replicate {} --sample {} --run-id {}",
                               plan.samples, plan.replicates, where.seed, where.replicate,
                               where.sample, stream_id(plan));
}

ReplayedSample replay_sample(const RunPlan& plan, std::uint64_t seed, std::uint32_t replicate,
                             std::uint64_t sample) {
  if (plan.render) {
    throw InputError(fmt::format(
        "command line: replay takes an analytic integrand; '{}' is a scene (a scene's sample is "
        "a whole image)",
        plan.integrand->name));
  }
  if (replicate >= plan.replicates) {
    throw InputError(fmt::format("command line: --replicate {} is outside the run: valid 0 to {}",
                                 replicate, plan.replicates - 1));
  }
  if (sample >= plan.samples) {
    throw InputError(fmt::format("command line: --sample {} is outside the run: valid 0 to {}",
                                 sample, plan.samples - 1));
  }
  ReplayedSample r;
  // The runner's batches: kBatchSize samples from a multiple of kBatchSize (chunks are whole
  // batches), the last one cut at N.
  r.batch_first = sample / kBatchSize * kBatchSize;
  r.batch_count =
      static_cast<std::uint32_t>(std::min<std::uint64_t>(kBatchSize, plan.samples - r.batch_first));
  const std::unique_ptr<PathWorkspace> paths = plan.made_integrand->make_workspace();
  r.estimate = evaluate(plan, seed, replicate, r.batch_first, r.batch_count, *paths)
                   .estimates[sample - r.batch_first];

  // Alone, the sample leaves its own paths in the workspace: camera path 0 and the pool from
  // light path 0 (a fresh pool, or its batch's shared pool).
  const BatchEvaluation alone = evaluate(plan, seed, replicate, sample, 1, *paths);
  r.estimate_alone = alone.estimates[0];
  if (!alone.log.empty()) {
    r.pmf = alone.log[0].pmf;
    r.draws = alone.log[0].draws;
  }
  const std::span<const double> p_y = paths->pdfs(PathSide::kCamera);
  const std::span<const double> p_x = paths->pdfs(PathSide::kLight);
  r.camera = {.pdf = p_y[0], .coordinates = paths->coordinates(PathSide::kCamera, 0)};
  const std::size_t M = r.pmf.empty() ? 1 : r.pmf.size();
  std::vector<PathPair> pairs;
  for (std::uint32_t j = 0; j < M && j < p_x.size(); ++j)
    pairs.push_back({.light = j, .camera = 0});
  std::vector<double> f(pairs.size());
  paths->connect(pairs, f);
  for (std::size_t j = 0; j < pairs.size(); ++j) {
    r.pool.push_back({.path = {.pdf = p_x[j],
                               .coordinates = paths->coordinates(PathSide::kLight,
                                                                 static_cast<std::uint32_t>(j))},
                      .f = f[j],
                      .contribution = f[j] / (p_x[j] * p_y[0])});
  }
  return r;
}

int run_replay(const RunPlan& plan, std::uint64_t seed, std::uint32_t replicate,
               std::uint64_t sample, const std::optional<std::string>& run_id, bool json,
               std::ostream& out) {
  if (run_id && *run_id != stream_id(plan)) {
    throw InputError(fmt::format(
        "command line: --run-id {}: these options rebuild run {}; give the estimator, "
        "integrand, every -p, --samples and --replicates of the run (as its replay command does)",
        *run_id, stream_id(plan)));
  }
  const ReplayedSample r = replay_sample(plan, seed, replicate, sample);
  if (json) {
    print_json(plan, seed, replicate, sample, r, out);
  } else {
    print_text(plan, seed, replicate, sample, r, out);
  }
  return std::isfinite(r.estimate) ? 0 : 3;
}

}  // namespace pcbench
