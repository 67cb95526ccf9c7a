// One replicate's contributions split by connection strategy (s, t), gathered while it renders
// (`--strategy-images`, results/strategy_images.h). The renderer adds each connection's weighted
// value here as well as to its pixel; nothing else changes, so the image keeps its bits.
//
// A layer exists for every strategy the estimator samples (StrategyCounts::count(s, t) > 0) with
// a path of 1 .. max_length edges (s + t - 1 ≤ max_length), whether or not it finds any light:
// the layers then depend on the estimator and the scene's path length only, never on the random
// numbers, and an all-black layer says "sampled, found nothing" (for instance s = 0 with point
// lights only) instead of leaving the reader to guess.
#pragma once

#include <cstdint>
#include <vector>

#include "integrands/scenes/connection.h"
#include "integrands/scenes/scene_math.h"
#include "results/strategy_images.h"

namespace pcbench::scene {

class StrategyTally {
 public:
  StrategyTally(const StrategyCounts& counts, std::uint32_t max_length, std::uint32_t width,
                std::uint32_t height);

  // Adds `value` to strategy (s, t) at `pixel` (y · width + x). Safe from several threads as
  // long as no two add to the same pixel at once (the renderer's rows; splats are merged on one
  // thread). Throws std::logic_error for a nonzero value of a strategy without a layer: the
  // renderer took a sample its MIS weights do not count.
  void add(std::uint32_t s, std::uint32_t t, std::uint32_t pixel, const Rgb& value);

  // The replicate's layers divided by its iteration count (one replicate of StrategyImages).
  StrategyImages per_iteration_mean(std::uint32_t iterations) &&;

 private:
  static constexpr int kNoLayer = -1;
  std::uint32_t max_length_;
  std::vector<int> layer_of_;  // (s, t) at s · (max_length + 2) + t
  StrategyImages images_;
};

}  // namespace pcbench::scene
