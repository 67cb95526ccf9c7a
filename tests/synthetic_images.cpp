#include "tests/synthetic_images.h"

#include <cmath>
#include <random>

namespace pcbench {

double true_mean(std::uint32_t x, std::uint32_t y, std::uint32_t c) {
  return 1.0 + 0.5 * std::sin(0.3 * x) * std::cos(0.2 * y) + 0.2 * c;
}

Image truth(std::uint32_t width, std::uint32_t height) {
  Image image(width, height);
  for (std::uint32_t y = 0; y < height; ++y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      for (std::uint32_t c = 0; c < kImageChannels; ++c) image.at(x, y, c) = true_mean(x, y, c);
    }
  }
  return image;
}

std::vector<Image> normal_replicates(std::uint32_t width, std::uint32_t height, std::uint32_t count,
                                     std::uint64_t seed, double sd) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sd);
  std::vector<Image> images;
  for (std::uint32_t r = 0; r < count; ++r) {
    Image image = truth(width, height);
    for (double& v : image.values) v += normal(rng);
    images.push_back(std::move(image));
  }
  return images;
}

}  // namespace pcbench
