#include "harness/verify/rounding_bound.h"

#include <cmath>

namespace pcbench {

double sample_roundings(const Counters& counters) {
  if (counters.camera_paths == 0) return kTermRoundings;
  const double per_sample = static_cast<double>(counters.connections) +
                            static_cast<double>(counters.importance_evaluations);
  return kTermRoundings + per_sample / static_cast<double>(counters.camera_paths);
}

double rounding_bound(const std::vector<ReplicateResult>& replicates, double sample_roundings) {
  if (replicates.empty()) return 0.0;
  // Plain sums: the bound's own rounding is far below its precision.
  double mean = 0.0, mean_abs = 0.0;
  for (const ReplicateResult& rep : replicates) {
    mean += rep.estimate;
    mean_abs += rep.mean_abs;
  }
  const double count = static_cast<double>(replicates.size());
  mean /= count;
  mean_abs /= count;
  return kUnitRoundoff * (sample_roundings * mean_abs + kMeanRoundings * std::fabs(mean));
}

}  // namespace pcbench
