// A scene run's per-strategy images (`--strategy-images`, results/strategy_images.h) as the run
// folder and the report hold them: one multi-layer EXR file, and the share of the image each
// strategy carries.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "results/image.h"
#include "results/strategy_images.h"

namespace pcbench {

// Writes every layer's mean image to `path` (atomically, 32-bit float, ZIP: results/exr_file.h)
// as the channels "s<s>_t<t>.R", ".G", ".B" (strategy_layer_name).
void write_strategy_exr(const std::filesystem::path& path, const StrategyImages& images);

// The report's image.strategies: per layer, in layer order, {s, t, layer, mean, share}: `mean`
// is the layer's mean over pixels and channels (the form of the run's estimate), `share` that
// mean over `run_mean`'s (null when the image is black). The shares sum to 1 up to rounding.
nlohmann::ordered_json strategy_shares_json(const StrategyImages& images, const Image& run_mean);

}  // namespace pcbench
