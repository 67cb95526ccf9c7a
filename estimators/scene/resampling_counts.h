// pcbpt's resampling-aware MIS counts (mis=resampling, pcbpt.cpp): the number of samples the K
// resampled draws of a camera vertex y effectively take of a light vertex of importance q*,
//     n(q*, y) = K M p̄,   p̄ = u / N_v + (1 - u) q* / (q* + (M - 1) Q̄(y)),
// the draw's probability for a candidate of importance q* among M light paths whose mean
// importance mass per path is Q̄(y) (the form M / ((M - 1) Q̄ / q* + 1) of the public
// re-implementations, times K, clamped by construction to [K M u / N_v, K M]). The balance
// heuristic with these counts gives a resampled connection to a bright light vertex the weight
// its many effective samples earn, and a dim one less than a uniform draw's.
//
// Q̄ and N_v come from the previous iteration's tables (learn()), per cell of a 16³ grid over the
// cache points' bounding box (the mean over the cell's cache points; the global mean where a
// cell has none), so the counts are a function of the path and of pools already used, never of
// the current pool: the weighted f stays independent of it (integrands/scenes/connection.h).
// Before the first learn() the counts are the constant ones.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "estimators/scene/cache_points.h"
#include "integrands/scenes/connection.h"

namespace pcbench::scene {

class ResamplingCounts final : public ConnectionCountModel {
 public:
  // `next_event_drawn`: the emitter vertices are candidates of the draws (pcbpt's nee=draws);
  // otherwise next-event strategies keep their constant count.
  ResamplingCounts(std::span<const CachePoint> points, std::uint32_t light_paths,
                   std::uint32_t draws, double uniform_mix, bool next_event_drawn);

  // One iteration's tables: per cache point Σ_i q_c(i) (0 for a point that sees nothing or has
  // no vertex), over `candidates` = N_v light vertices.
  void learn(std::span<const double> totals, std::uint32_t candidates);

  double count(double importance, const Vec3& camera_end, double constant) const override;
  bool counts_next_event() const override { return next_event_drawn_; }

 private:
  static constexpr std::uint32_t kCells = 16;  // per axis
  std::uint32_t cell_of(const Vec3& position) const;

  std::span<const CachePoint> points_;
  double m_, k_, u_;
  bool next_event_drawn_;
  Vec3 low_ = {}, cell_size_ = {1.0, 1.0, 1.0};
  std::vector<double> mean_mass_;     // per cell: Q̄, the mean importance mass per light path
  double uniform_probability_ = 0.0;  // 1 / N_v
  bool learned_ = false;
};

}  // namespace pcbench::scene
