// Synthetic replicate images for the image tests (pixel statistics, block pyramids): a smooth
// positive scene and replicates of a sampler whose pixels are independent normals around it.
#pragma once

#include <cstdint>
#include <vector>

#include "results/image.h"

namespace pcbench {

// The true mean of the synthetic scene: smooth, positive, different per channel.
double true_mean(std::uint32_t x, std::uint32_t y, std::uint32_t c);

// The synthetic scene's exact image.
Image truth(std::uint32_t width, std::uint32_t height);

// `count` replicates whose pixels are independent normals of deviation `sd` around true_mean
// (std::mt19937_64 seeded with `seed`).
std::vector<Image> normal_replicates(std::uint32_t width, std::uint32_t height, std::uint32_t count,
                                     std::uint64_t seed, double sd);

}  // namespace pcbench
