// The mean image of each (s, t) connection strategy of a scene run (`--strategy-images`): s light
// subpath vertices joined with t camera subpath vertices (integrands/scenes/connection.h), each
// layer holding the strategy's MIS-weighted contribution per pixel. Over all layers they sum to
// the run's mean image, so they show where a bidirectional estimator's energy (and noise) comes
// from.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "results/image.h"

namespace pcbench {

struct StrategyLayer {
  std::uint32_t s = 0;  // light subpath vertices
  std::uint32_t t = 0;  // camera subpath vertices
  Image image;
};

struct StrategyImages {
  // The layers of the strategies the estimator samples, shortest paths first (path length
  // s + t - 1, then s). Each holds the sum over `replicates` replicates of that replicate's
  // per-pixel mean over its iterations: sums, so that parts of a run taken apart (interleaved,
  // harness/run/interleaved_runs.h) add up to the run taken whole.
  std::vector<StrategyLayer> layers;
  std::uint32_t replicates = 0;

  // Adds the replicates of `other`, which must have the same layers and size (the same run).
  // Throws std::invalid_argument when they do not.
  void add(const StrategyImages& other);

  // Layer `index` divided by the replicate count: the strategy's mean image over the run.
  Image mean(std::size_t index) const;
};

// Adds `part` (a later replicate or part of the same run) to `total`, which takes it whole while
// it has nothing; nothing to add leaves `total` as it is.
void add_strategy_images(std::optional<StrategyImages>& total,
                         std::optional<StrategyImages>&& part);

// A layer's name in the EXR file and the report: "s<s>_t<t>", e.g. "s0_t3" (a camera path of
// three vertices that hits an emitter) or "s2_t1" (light tracing of a two-vertex light path).
std::string strategy_layer_name(std::uint32_t s, std::uint32_t t);

}  // namespace pcbench
