#include "harness/verify/tile_checks.h"

#include <algorithm>
#include <stdexcept>

namespace pcbench {

std::optional<Image> exact_image(const SceneIntegrand& scene) {
  if (!scene.exact_radiance()) return std::nullopt;
  const scene::Rgb& value = *scene.exact_radiance();
  Image image(scene.scene().description().width, scene.scene().description().height);
  for (std::size_t i = 0; i < image.values.size(); ++i) image.values[i] = value[i % 3];
  return image;
}

const TileTest& brightest_tile(const TileTestResult& result) {
  if (result.tiles.empty()) throw std::invalid_argument("brightest_tile: no tiles");
  return *std::max_element(
      result.tiles.begin(), result.tiles.end(),
      [](const TileTest& x, const TileTest& y) { return x.mean_a < y.mean_a; });
}

std::vector<Image> with_tile_bias(std::vector<Image> images, const TileTest& tile,
                                  std::uint32_t tile_size, double bias) {
  for (Image& image : images) {
    const std::uint32_t x_end = std::min(image.width, (tile.tile_x + 1) * tile_size);
    const std::uint32_t y_end = std::min(image.height, (tile.tile_y + 1) * tile_size);
    for (std::uint32_t y = tile.tile_y * tile_size; y < y_end; ++y) {
      for (std::uint32_t x = tile.tile_x * tile_size; x < x_end; ++x) {
        image.at(x, y, tile.channel) += bias;
      }
    }
  }
  return images;
}

}  // namespace pcbench
