// What the block tests' self-checks share: the verifier's 2×MDB check per scene and scale
// (harness/verify/scene_verification.cpp, harness/commands/image_set_verify.cpp) and the tile
// calibration (harness/commands/tile_calibration.h) plant a bias into the same block of the same
// run in the same way, so that what the calibration measures is the check a session runs.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "harness/verify/block_pyramid.h"
#include "integrands/scenes/scene_integrand.h"
#include "results/image.h"

namespace pcbench {

// The scene's exact image (the furnace's constant radiance in every pixel), or nothing.
std::optional<Image> exact_image(const SceneIntegrand& scene);

// The block×channel test of one scale a planted bias goes into: the brightest one (largest block
// mean of the run the bias is added to), where a bias of a given relative size is largest and the
// scene's light is. Throws std::invalid_argument when the scale has no tests.
const BlockTest& brightest_block(const ScaleTests& scale);

// `images` with `bias` added to channel `block.channel` of every pixel of block (x, y) (blocks of
// block_size pixels, cut by the border as the tests cut them): in distribution a run whose
// expectation is off by `bias` there and nowhere else, with the same spread.
std::vector<Image> with_block_bias(std::vector<Image> images, const BlockTest& block,
                                   std::uint32_t block_size, double bias);

}  // namespace pcbench
