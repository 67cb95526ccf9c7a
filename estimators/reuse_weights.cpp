#include "estimators/reuse_weights.h"

namespace pcbench {
namespace {

// 1[T_s > 0] / #{t: T_t > 0}.
double count_weight(std::span<const double> targets, std::size_t s) {
  if (!(targets[s] > 0.0)) return 0.0;
  double z = 0.0;
  for (double t : targets) z += t > 0.0 ? 1.0 : 0.0;
  return 1.0 / z;
}

double balance_weight(std::span<const double> targets, std::size_t s) {
  double total = 0.0;
  for (double t : targets) total += t;
  return total > 0.0 ? targets[s] / total : 0.0;
}

// T_a / (T_a + T_b), 0 when both are 0 (neither source can produce x).
double pair_share(double a, double b) {
  return a + b > 0.0 ? a / (a + b) : 0.0;
}

double pairwise_weight(std::span<const double> targets, std::size_t s) {
  const double k1 = static_cast<double>(targets.size());  // k + 1
  const double canonical = targets[0];
  if (s != 0) return pair_share(targets[s], canonical) / k1;
  double m = 1.0;
  for (std::size_t r = 1; r < targets.size(); ++r) m += pair_share(canonical, targets[r]);
  return m / k1;
}

}  // namespace

double reuse_mis_weight(const ReuseWeighting& weighting, std::span<const double> targets,
                        std::size_t s) {
  switch (weighting.form) {
    case ReuseWeights::kBalance:
      return balance_weight(targets, s);
    case ReuseWeights::kPairwise:
      return pairwise_weight(targets, s);
    case ReuseWeights::kCount:
      return count_weight(targets, s);
    case ReuseWeights::kUniform: {
      const double share = weighting.naive_share;
      return (1.0 - share) * count_weight(targets, s) + share / static_cast<double>(targets.size());
    }
  }
  return 0.0;
}

}  // namespace pcbench
