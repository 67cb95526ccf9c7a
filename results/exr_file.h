// OpenEXR files of 32-bit float channels: scene images and their statistics (mean, standard
// error, z maps) written for inspection, and cached reference images read back.
//
// Channels are FLOAT, never HALF: a reference image or a z map read back must hold the numbers
// the tests compared, and half precision (11 significant bits) would round them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "results/image.h"

namespace pcbench {

struct ExrChannel {
  std::string name;
  std::vector<float> values;  // width * height, row-major, top row first
};

// Writes the channels as FLOAT with ZIP compression (lossless). The file is written to
// "<path>.tmp" and renamed onto `path`, so a reader never sees half a file; the temporary is
// removed if writing fails. Throws std::invalid_argument for a zero or too large size, no
// channels, an empty or repeated name, or a channel whose size is not width * height, and
// std::runtime_error when the file cannot be written.
void write_exr(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
               const std::vector<ExrChannel>& channels);

// An Image's three channels (rounded to float) named R, G, B, or "<layer>.R", "<layer>.G",
// "<layer>.B" for a layer of a multi-layer file (the OpenEXR naming convention tools show as
// layers). Throws std::invalid_argument when the values do not match the image's size.
std::vector<ExrChannel> rgb_channels(const Image& image, const std::string& layer = "");

// An Image's three channels as R, G, B (rounded to float).
void write_exr_rgb(const std::filesystem::path& path, const Image& image);

// Reads every FLOAT channel of a scanline or tiled file, in the file's channel order (OpenEXR
// keeps channels sorted by name: B, G, R). Channels of other types are skipped. Sets width and
// height to the data window's. Throws std::runtime_error when the file cannot be read.
std::vector<ExrChannel> read_exr(const std::filesystem::path& path, std::uint32_t& width,
                                 std::uint32_t& height);

}  // namespace pcbench
