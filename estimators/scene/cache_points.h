// Cache points of probabilistic connections (pcbpt.cpp): camera-subpath vertices traced once per
// replicate from a sparse screen grid, each standing for the camera vertices near it when an
// iteration's light vertices are weighed. They depend on no pool (their streams are the
// replicate's kEstimatorAux), so the distributions built at them keep f independent of the pool.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "integrands/scenes/render_services.h"

namespace pcbench::scene {

struct CachePoint {
  Subpath camera;  // y_0 .. y_d: the cache path up to this point (d = depth); empty: no hit
  std::uint32_t depth = 1;
  const PathVertex& vertex() const { return camera.back(); }
};

// The screen cut into blocks of `block` × `block` pixels, each with one cache path through its
// centre. first_hit_only: the legacy design, one cache point per block at the first hit (the slot
// exists, with an empty path, when the centre sees nothing). Otherwise every non-specular surface
// vertex of the cache path (up to max_length) is a cache point.
class CachePoints {
 public:
  CachePoints(const RenderServices& services, std::uint32_t block, bool first_hit_only);

  std::span<const CachePoint> points() const { return points_; }
  std::uint32_t block_of(std::uint32_t pixel) const;
  // The cache point of `block` at camera depth `depth` (>= 1), if its path has one there.
  std::optional<std::uint32_t> at(std::uint32_t block, std::uint32_t depth) const;

 private:
  std::uint32_t width_, block_, blocks_x_, max_depth_;
  std::vector<CachePoint> points_;
  std::vector<std::int32_t> slot_;  // block × max_depth → index into points_, -1 for none
};

// The nearest cache points of a position: a kd-tree (nanoflann) over the points' positions.
class NearestCachePoints {
 public:
  static constexpr std::uint32_t kMaxFound = 64;  // the most points one find() returns

  explicit NearestCachePoints(std::span<const CachePoint> points);
  ~NearestCachePoints();
  // Up to `count` (at most kMaxFound) indices into the points, nearest first; returns how many.
  std::uint32_t find(const Vec3& position, std::uint32_t count, std::uint32_t* indices) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace pcbench::scene
