// An RGB image of doubles: what a scene run produces per replicate, and what the statistics,
// the EXR writer and the comparisons read. Row-major, top row first, three channels per pixel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcbench {

inline constexpr std::uint32_t kImageChannels = 3;

struct Image {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<double> values = {};  // (y * width + x) * 3 + channel

  Image() = default;
  Image(std::uint32_t w, std::uint32_t h)
      : width(w), height(h), values(std::size_t{w} * h * kImageChannels, 0.0) {}

  std::size_t pixel_count() const { return std::size_t{width} * height; }
  double& at(std::uint32_t x, std::uint32_t y, std::uint32_t channel) {
    return values[(std::size_t{y} * width + x) * kImageChannels + channel];
  }
  double at(std::uint32_t x, std::uint32_t y, std::uint32_t channel) const {
    return values[(std::size_t{y} * width + x) * kImageChannels + channel];
  }
};

}  // namespace pcbench
