#include "estimators/scene/resampling_counts.h"

#include <algorithm>
#include <cmath>

namespace pcbench::scene {

ResamplingCounts::ResamplingCounts(std::span<const CachePoint> points, std::uint32_t light_paths,
                                   std::uint32_t draws, double uniform_mix, bool next_event_drawn)
    : points_(points),
      m_(light_paths),
      k_(draws),
      u_(uniform_mix),
      next_event_drawn_(next_event_drawn) {
  bool any = false;
  Vec3 high = {};
  for (const CachePoint& point : points_) {
    if (point.camera.empty()) continue;
    const Vec3& p = point.vertex().position;
    low_ = any ? Vec3{std::min(low_.x, p.x), std::min(low_.y, p.y), std::min(low_.z, p.z)} : p;
    high = any ? Vec3{std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)} : p;
    any = true;
  }
  // A flat box (cache points on one wall) still gets cells of a positive size.
  const auto size = [](double extent) { return std::max(extent, 1e-6) / kCells; };
  cell_size_ = {size(high.x - low_.x), size(high.y - low_.y), size(high.z - low_.z)};
}

std::uint32_t ResamplingCounts::cell_of(const Vec3& position) const {
  const auto axis = [](double value, double low, double size) {
    const double cell = std::floor((value - low) / size);
    return static_cast<std::uint32_t>(std::clamp(cell, 0.0, double{kCells - 1}));
  };
  return (axis(position.z, low_.z, cell_size_.z) * kCells +
          axis(position.y, low_.y, cell_size_.y)) *
             kCells +
         axis(position.x, low_.x, cell_size_.x);
}

void ResamplingCounts::learn(std::span<const double> totals, std::uint32_t candidates) {
  learned_ = candidates > 0;
  if (!learned_) return;
  uniform_probability_ = 1.0 / candidates;
  std::vector<double> sum(kCells * kCells * kCells, 0.0);
  std::vector<std::uint32_t> points_in(sum.size(), 0);
  double global_sum = 0.0;
  std::uint32_t global_points = 0;
  for (std::size_t c = 0; c < points_.size(); ++c) {
    if (points_[c].camera.empty()) continue;
    const double mass = totals[c] / m_;
    const std::uint32_t cell = cell_of(points_[c].vertex().position);
    sum[cell] += mass;
    ++points_in[cell];
    global_sum += mass;
    ++global_points;
  }
  const double global_mean = global_points > 0 ? global_sum / global_points : 0.0;
  mean_mass_.resize(sum.size());
  for (std::size_t cell = 0; cell < sum.size(); ++cell) {
    mean_mass_[cell] = points_in[cell] > 0 ? sum[cell] / points_in[cell] : global_mean;
  }
}

double ResamplingCounts::count(double importance, const Vec3& camera_end, double constant) const {
  if (!learned_ || importance < 0.0) return constant;
  const double mass = mean_mass_[cell_of(camera_end)];
  // A region whose cache points see nothing draws uniformly there (CacheMixture).
  const double guided =
      mass > 0.0 ? importance / (importance + (m_ - 1.0) * mass) : uniform_probability_;
  return k_ * m_ * (u_ * uniform_probability_ + (1.0 - u_) * guided);
}

}  // namespace pcbench::scene
