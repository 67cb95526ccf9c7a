#include "integrands/scenes/strategy_tally.h"

#include <fmt/format.h>

#include <stdexcept>

namespace pcbench::scene {

StrategyTally::StrategyTally(const StrategyCounts& counts, std::uint32_t max_length,
                             std::uint32_t width, std::uint32_t height)
    : max_length_(max_length), layer_of_(std::size_t{max_length + 2} * (max_length + 2), kNoLayer) {
  // A path of k edges has k + 1 vertices, split as s light + t camera vertices with t ≥ 1 (the
  // camera vertex y_0 is never on a light path) and s + t = k + 1.
  for (std::uint32_t k = 1; k <= max_length; ++k) {
    for (std::uint32_t s = 0; s <= k; ++s) {
      const std::uint32_t t = k + 1 - s;
      if (counts.count(s, t) <= 0.0) continue;
      layer_of_[std::size_t{s} * (max_length + 2) + t] = static_cast<int>(images_.layers.size());
      images_.layers.push_back({.s = s, .t = t, .image = Image(width, height)});
    }
  }
  images_.replicates = 1;
}

void StrategyTally::add(std::uint32_t s, std::uint32_t t, std::uint32_t pixel, const Rgb& value) {
  const int layer =
      s + t <= max_length_ + 1 ? layer_of_[std::size_t{s} * (max_length_ + 2) + t] : kNoLayer;
  if (layer == kNoLayer) {
    if (value.is_black()) return;
    throw std::logic_error(
        fmt::format("strategy {} contributed although the estimator does not sample it",
                    strategy_layer_name(s, t)));
  }
  double* values = images_.layers[static_cast<std::size_t>(layer)].image.values.data();
  values[3 * std::size_t{pixel} + 0] += value.r;
  values[3 * std::size_t{pixel} + 1] += value.g;
  values[3 * std::size_t{pixel} + 2] += value.b;
}

StrategyImages StrategyTally::per_iteration_mean(std::uint32_t iterations) && {
  for (StrategyLayer& layer : images_.layers) {
    for (double& v : layer.image.values) v /= iterations;
  }
  return std::move(images_);
}

}  // namespace pcbench::scene
