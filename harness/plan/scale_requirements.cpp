#include "harness/plan/scale_requirements.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>

#include "base/errors.h"

namespace pcbench {
namespace {

constexpr std::string_view kValidScales =
    "tile (the finest blocks), image (the whole image) or a block edge in pixels, tile × 2^k "
    "(8, 16, 32, ... with 8×8 tiles)";

std::uint32_t scale_key(std::string_view scale, std::string_view where) {
  if (scale == "tile") return ScaleRequirements::kTileScale;
  if (scale == "image") return ScaleRequirements::kImageScale;
  std::uint32_t block = 0;
  const auto [end, error] = std::from_chars(scale.data(), scale.data() + scale.size(), block);
  if (error != std::errc() || end != scale.data() + scale.size() || block == 0 ||
      block == ScaleRequirements::kImageScale) {
    throw InputError(fmt::format("{}: scale '{}' is not one of: {}", where, scale, kValidScales));
  }
  return block;
}

}  // namespace

void ScaleRequirements::set(std::string_view scale, double fraction, std::string_view where) {
  const std::uint32_t key = scale_key(scale, where);
  if (!(fraction > 0.0 && fraction < 1.0)) {
    throw InputError(fmt::format(
        "{}: the required detectable bias at scale {} is {}, not a fraction in (0, 1) (0.05 is 5% "
        "of a bright block's mean)",
        where, scale, fraction));
  }
  max_relative_mdb[key] = fraction;
}

void ScaleRequirements::drop(std::string_view scale, std::string_view where) {
  max_relative_mdb.erase(scale_key(scale, where));
}

void ScaleRequirements::set(std::string_view assignment, std::string_view where) {
  const std::size_t equals = assignment.find('=');
  if (equals == std::string_view::npos) {
    throw InputError(
        fmt::format("{}: '{}' is not SCALE=FRACTION (for example image=0.01)", where, assignment));
  }
  const std::string_view value = assignment.substr(equals + 1);
  if (value == "none") return drop(assignment.substr(0, equals), where);
  double fraction = 0.0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), fraction);
  if (error != std::errc() || end != value.data() + value.size()) {
    throw InputError(fmt::format("{}: '{}' is not SCALE=FRACTION: '{}' is not a number", where,
                                 assignment, value));
  }
  set(assignment.substr(0, equals), fraction, where);
}

void ScaleRequirements::check_blocks(std::uint32_t tile, std::string_view where) const {
  for (const auto& [key, fraction] : max_relative_mdb) {
    if (key == kTileScale || key == kImageScale) continue;
    std::uint64_t block = tile;
    while (block < key) block *= 2;
    if (block != key) {
      throw InputError(fmt::format(
          "{}: block edge {} is not a scale of the pyramid of {}-pixel tiles: {}, {}, {}, ... "
          "(or tile, image)",
          where, key, tile, tile, 2 * tile, 4 * tile));
    }
  }
}

std::optional<double> ScaleRequirements::at(std::uint32_t block, bool finest, bool whole) const {
  std::optional<double> out;
  const auto take = [&](std::uint32_t key) {
    const auto it = max_relative_mdb.find(key);
    if (it != max_relative_mdb.end()) out = std::min(out.value_or(1.0), it->second);
  };
  take(block);
  if (finest) take(kTileScale);
  if (whole) take(kImageScale);
  return out;
}

std::string scale_name(std::uint32_t key) {
  if (key == ScaleRequirements::kTileScale) return "tile";
  if (key == ScaleRequirements::kImageScale) return "image";
  return std::to_string(key);
}

}  // namespace pcbench
