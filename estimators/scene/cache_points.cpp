#include "estimators/scene/cache_points.h"

#include <nanoflann.hpp>

#include <algorithm>

namespace pcbench::scene {

CachePoints::CachePoints(const RenderServices& services, std::uint32_t block, bool first_hit_only)
    : width_(services.width()),
      block_(block),
      blocks_x_((services.width() + block - 1) / block),
      max_depth_(first_hit_only ? 1 : services.max_length()) {
  const std::uint32_t blocks_y = (services.height() + block - 1) / block;
  const double width = services.width(), height = services.height();
  slot_.assign(std::size_t{blocks_x_} * blocks_y * max_depth_, -1);
  TraceCounters ignored;  // the cache paths are the estimator's set-up, not an iteration's work
  Subpath path;
  for (std::uint32_t by = 0; by < blocks_y; ++by) {
    for (std::uint32_t bx = 0; bx < blocks_x_; ++bx) {
      const std::uint32_t b = by * blocks_x_ + bx;
      const double cx = std::min<double>(width, (bx + 0.5) * block);
      const double cy = std::min<double>(height, (by + 0.5) * block);
      RandomStream rng(services.stream(StreamPurpose::kEstimatorAux, 0, b));
      trace_camera_path(services.scene(), std::min(cx, width - 0.5), std::min(cy, height - 0.5),
                        rng, max_depth_, path, ignored);
      for (std::uint32_t d = 1; d <= max_depth_; ++d) {
        const bool hit = d < path.size();
        if (!first_hit_only && (!hit || path[d].delta)) continue;
        slot_[std::size_t{b} * max_depth_ + (d - 1)] = static_cast<std::int32_t>(points_.size());
        CachePoint& point = points_.emplace_back();
        point.depth = d;
        // The legacy slot stays empty when its centre sees nothing (an importance of zero).
        if (hit) point.camera.insert(point.camera.end(), path.begin(), path.begin() + d + 1);
      }
    }
  }
}

std::uint32_t CachePoints::block_of(std::uint32_t pixel) const {
  const std::uint32_t x = pixel % width_, y = pixel / width_;
  return (y / block_) * blocks_x_ + x / block_;
}

std::optional<std::uint32_t> CachePoints::at(std::uint32_t block, std::uint32_t depth) const {
  if (depth == 0 || depth > max_depth_) return std::nullopt;
  const std::int32_t index = slot_[std::size_t{block} * max_depth_ + (depth - 1)];
  if (index < 0) return std::nullopt;
  return static_cast<std::uint32_t>(index);
}

// nanoflann's dataset adaptor over the cache points' positions.
struct PositionCloud {
  std::vector<Vec3> positions;
  std::size_t kdtree_get_point_count() const { return positions.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    const Vec3& p = positions[i];
    return dim == 0 ? p.x : dim == 1 ? p.y : p.z;
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

struct NearestCachePoints::Tree {
  using Index =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PositionCloud>,
                                          PositionCloud, 3, std::uint32_t>;
  PositionCloud cloud;
  std::vector<std::uint32_t> point_of;  // tree entry → cache point (points with no vertex left out)
  std::unique_ptr<Index> index;
};

// GCC 12 sees a possible null dereference in nanoflann's index vector resize (std::vector::resize
// inlined into buildIndex), a false positive of -Wnull-dereference at -O3 in a system header.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
NearestCachePoints::NearestCachePoints(std::span<const CachePoint> points)
    : tree_(std::make_unique<Tree>()) {
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    if (points[i].camera.empty()) continue;
    tree_->cloud.positions.push_back(points[i].vertex().position);
    tree_->point_of.push_back(i);
  }
  tree_->index =
      std::make_unique<Tree::Index>(3, tree_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
}
#pragma GCC diagnostic pop

NearestCachePoints::~NearestCachePoints() = default;

std::uint32_t NearestCachePoints::find(const Vec3& position, std::uint32_t count,
                                       std::uint32_t* indices) const {
  if (tree_->point_of.empty() || count == 0) return 0;
  const double query[3] = {position.x, position.y, position.z};
  double distances[kMaxFound];
  count = std::min(count, kMaxFound);
  const auto found =
      static_cast<std::uint32_t>(tree_->index->knnSearch(query, count, indices, distances));
  for (std::uint32_t i = 0; i < found; ++i) indices[i] = tree_->point_of[indices[i]];
  return found;
}

}  // namespace pcbench::scene
