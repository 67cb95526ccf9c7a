#include "harness/verify/image_errors.h"

#include <algorithm>
#include <cmath>

#include "harness/verify/image_statistics.h"

namespace pcbench {
namespace {

struct Errors {
  double mse = 0.0;  // mean over values of (x − ref)²
  double rel = 0.0;  // mean over values of (x − ref)² / scale²
};

Errors errors_of(const Image& x, const Image& reference, const std::vector<double>& scale) {
  Errors e;
  for (std::size_t i = 0; i < x.values.size(); ++i) {
    const double d = x.values[i] - reference.values[i];
    e.mse += d * d;
    e.rel += d * d / (scale[i] * scale[i]);
  }
  const double n = static_cast<double>(std::max<std::size_t>(1, x.values.size()));
  return {e.mse / n, e.rel / n};
}

}  // namespace

nlohmann::ordered_json image_error_fields(std::span<const Image> replicates,
                                          std::span<const ReplicateResult> results,
                                          const Image& mean, const Image& reference,
                                          const Image* reference_stderr) {
  const std::vector<double> scale = relative_error_scale(reference);
  // The reference's own variance, absolute and relative, averaged over values.
  Errors own;
  if (reference_stderr) {
    for (double se : reference_stderr->values) own.mse += se * se;
    own.mse /= static_cast<double>(std::max<std::size_t>(1, reference_stderr->values.size()));
    own.rel = relative_variance(reference, *reference_stderr);
  }
  const Errors of_mean = errors_of(mean, reference, scale);
  double rel_replicate = 0.0, cpu = 0.0;
  for (std::size_t k = 0; k < replicates.size(); ++k) {
    rel_replicate += errors_of(replicates[k], reference, scale).rel;
    cpu += results[k].cpu_seconds;
  }
  const double count = static_cast<double>(std::max<std::size_t>(1, replicates.size()));
  rel_replicate /= count;
  cpu /= count;
  // Unbiased after the subtraction, but a noisy reference can make it negative: an error is
  // never below 0, and reference_rel_variance says how much was taken off.
  const double rel_replicate_run = std::max(0.0, rel_replicate - own.rel);
  const double at_1_second = rel_replicate_run * cpu;
  return {{"rmse", std::sqrt(std::max(0.0, of_mean.mse - own.mse))},
          {"rel_mse", std::max(0.0, of_mean.rel - own.rel)},
          {"rel_mse_per_replicate", rel_replicate_run},
          {"reference_rel_variance", own.rel},
          {"cpu_seconds_per_replicate", cpu},
          {"rel_mse_at_1_cpu_second", at_1_second},
          {"efficiency", at_1_second > 0.0 ? 1.0 / at_1_second : 0.0}};
}

}  // namespace pcbench
