#include "harness/verify/strategy_image_file.h"

#include <vector>

#include "results/exr_file.h"

namespace pcbench {
namespace {

// Over pixels and channels, as a scene replicate's estimate is (harness/run/scene_runner.h).
double image_mean(const Image& image) {
  double sum = 0.0;
  for (double v : image.values) sum += v;
  return image.values.empty() ? 0.0 : sum / static_cast<double>(image.values.size());
}

}  // namespace

void write_strategy_exr(const std::filesystem::path& path, const StrategyImages& images) {
  std::vector<ExrChannel> channels;
  std::uint32_t width = 0, height = 0;
  for (std::size_t i = 0; i < images.layers.size(); ++i) {
    const StrategyLayer& layer = images.layers[i];
    width = layer.image.width;
    height = layer.image.height;
    for (ExrChannel& channel :
         rgb_channels(images.mean(i), strategy_layer_name(layer.s, layer.t))) {
      channels.push_back(std::move(channel));
    }
  }
  write_exr(path, width, height, channels);
}

nlohmann::ordered_json strategy_shares_json(const StrategyImages& images, const Image& run_mean) {
  const double total = image_mean(run_mean);
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < images.layers.size(); ++i) {
    const StrategyLayer& layer = images.layers[i];
    const double mean = image_mean(images.mean(i));
    out.push_back({{"s", layer.s},
                   {"t", layer.t},
                   {"layer", strategy_layer_name(layer.s, layer.t)},
                   {"mean", mean},
                   {"share", total != 0.0 ? nlohmann::ordered_json(mean / total)
                                          : nlohmann::ordered_json(nullptr)}});
  }
  return out;
}

}  // namespace pcbench
