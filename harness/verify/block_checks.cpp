#include "harness/verify/block_checks.h"

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

const BlockTest& brightest_block(const ScaleTests& scale) {
  if (scale.tests.empty()) throw std::invalid_argument("brightest_block: no blocks");
  return *std::max_element(
      scale.tests.begin(), scale.tests.end(),
      [](const BlockTest& x, const BlockTest& y) { return x.mean_a < y.mean_a; });
}

std::vector<Image> with_block_bias(std::vector<Image> images, const BlockTest& block,
                                   std::uint32_t block_size, double bias) {
  for (Image& image : images) {
    const std::uint32_t x_end = std::min(image.width, (block.x + 1) * block_size);
    const std::uint32_t y_end = std::min(image.height, (block.y + 1) * block_size);
    for (std::uint32_t y = block.y * block_size; y < y_end; ++y) {
      for (std::uint32_t x = block.x * block_size; x < x_end; ++x) {
        image.at(x, y, block.channel) += bias;
      }
    }
  }
  return images;
}

}  // namespace pcbench
