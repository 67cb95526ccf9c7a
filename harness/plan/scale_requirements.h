// What a scene comparison's power must reach at each scale of its block pyramid
// (harness/verify/block_pyramid.h): the largest detectable bias relative to a bright block's mean.
// By default the whole image must see 1% and the finest blocks (8×8 tiles) 5%; a suite's
// "require_mdb" or the command line's --require-mdb SCALE=FRACTION changes one scale or adds
// another (docs/reference/INTERFACE.md, `test: "block-pyramid"`).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace pcbench {

struct ScaleRequirements {
  // Keys: kTileScale, kImageScale, or a block edge in pixels; values in (0, 1).
  static constexpr std::uint32_t kTileScale = 0;
  static constexpr std::uint32_t kImageScale = UINT32_MAX;
  std::map<std::uint32_t, double> max_relative_mdb = {{kTileScale, 0.05}, {kImageScale, 0.01}};

  // Sets the requirement of SCALE ("tile", "image" or a block edge in pixels) to `fraction`.
  // Throws InputError naming `where` for another scale name or a fraction outside (0, 1).
  void set(std::string_view scale, double fraction, std::string_view where);
  // Drops the requirement of SCALE (a suite's null, the command line's SCALE=none): a scale no
  // budget can serve, such as door-ajar's 8×8 tiles, then states its power without one.
  void drop(std::string_view scale, std::string_view where);
  // Parses and sets "SCALE=FRACTION" (or drops it: "SCALE=none").
  void set(std::string_view assignment, std::string_view where);
  // Throws InputError naming `where` when a block edge is not tile × 2^k for the tile size given.
  void check_blocks(std::uint32_t tile, std::string_view where) const;

  // The requirement of the scale whose blocks have edge `block` (the finest: `finest`, the one
  // covering the image: `whole`); the strictest where several keys name it; nothing where none
  // does.
  std::optional<double> at(std::uint32_t block, bool finest, bool whole) const;
};

// "tile", "image" or the edge in pixels, for messages and reports.
std::string scale_name(std::uint32_t key);

}  // namespace pcbench
