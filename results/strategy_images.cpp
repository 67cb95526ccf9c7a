#include "results/strategy_images.h"

#include <fmt/format.h>

#include <stdexcept>

namespace pcbench {

void StrategyImages::add(const StrategyImages& other) {
  if (other.layers.size() != layers.size()) {
    throw std::invalid_argument(fmt::format("strategy images with {} layers added to {}",
                                            other.layers.size(), layers.size()));
  }
  for (std::size_t i = 0; i < layers.size(); ++i) {
    StrategyLayer& to = layers[i];
    const StrategyLayer& from = other.layers[i];
    if (from.s != to.s || from.t != to.t || from.image.values.size() != to.image.values.size()) {
      throw std::invalid_argument(fmt::format("strategy layer {} added to {} of another size",
                                              strategy_layer_name(from.s, from.t),
                                              strategy_layer_name(to.s, to.t)));
    }
    for (std::size_t k = 0; k < to.image.values.size(); ++k) {
      to.image.values[k] += from.image.values[k];
    }
  }
  replicates += other.replicates;
}

Image StrategyImages::mean(std::size_t index) const {
  Image out = layers.at(index).image;
  if (replicates > 0) {
    for (double& v : out.values) v /= replicates;
  }
  return out;
}

void add_strategy_images(std::optional<StrategyImages>& total,
                         std::optional<StrategyImages>&& part) {
  if (!part) return;
  if (total) {
    total->add(*part);
  } else {
    total = std::move(part);
  }
}

std::string strategy_layer_name(std::uint32_t s, std::uint32_t t) {
  return fmt::format("s{}_t{}", s, t);
}

}  // namespace pcbench
