// What the tile tests' self-checks share: the verifier's 2×MDB check per scene
// (harness/verify/scene_verification.cpp) and the tile calibration
// (harness/commands/tile_calibration.h) plant a bias into the same tile of the same run in the same
// way, so that what the calibration measures is the check a session runs.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "harness/verify/image_statistics.h"
#include "integrands/scenes/scene_integrand.h"
#include "results/image.h"

namespace pcbench {

// The scene's exact image (the furnace's constant radiance in every pixel), or nothing.
std::optional<Image> exact_image(const SceneIntegrand& scene);

// The tile×channel test a planted bias goes into: the brightest one of side a (largest tile mean
// of the run the bias is added to), where a bias of a given relative size is largest and the
// scene's light is. Throws std::invalid_argument when `result` has no tiles.
const TileTest& brightest_tile(const TileTestResult& result);

// `images` with `bias` added to channel `tile.channel` of every pixel of tile (tile_x, tile_y)
// (tiles of tile_size pixels, cut by the border as the tests cut them): in distribution a run
// whose expectation is off by `bias` there and nowhere else, with the same spread.
std::vector<Image> with_tile_bias(std::vector<Image> images, const TileTest& tile,
                                  std::uint32_t tile_size, double bias);

}  // namespace pcbench
