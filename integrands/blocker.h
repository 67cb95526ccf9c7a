// blocker: flatland transport between two parallel unit segments with an occluding strip between
// them. Light point (x0, 0), camera point (y0, h), a strip on the line z = t h covering
// [m - w/2, m + w/2]; 1 + 1 dimensions:
//
//     f(x, y) = k(y0 - x0) V(x, y),   k(u) = h² / (2 r³),   r² = h² + u²,
//     V = 0 if the segment x -> y crosses the strip (c = x0 + t (y0 - x0) in [m - w/2, m + w/2]),
//     else 1.
//
// k is the flatland form factor's kernel, cos θ_x cos θ_y / (2 r).
//
// Parameters: distance h (default 1, [0.01, 100]), strip_height t (0.5, a fraction of h,
// [0.01, 0.99]), strip_center m (0.6, [0, 1]), strip_width w (0.4, [0, 2]).
//
// Exact value (kExact): the unoccluded total √(1 + h²) - h (Hottel's crossed strings) minus the
// part through the strip, ∫∫ k 1[c in strip], which is a closed form too: for fixed x0 the
// passing offsets u form an interval whose ends are affine in x0 between known kinks, and k has
// the antiderivative u / (2 √(h² + u²)) (parallel::flatland_through). At the defaults:
// I = 0.1788289...
//
// Sampling: uniform, p(x) = p(y) = 1.
// approximate_importance(x, y) = k(y0 - x0), the unoccluded kernel (> 0 everywhere).
//
// Stresses: visibility that zeroes f for part of the pairs (here about half of them), so an
// importance without visibility wastes draws on blocked connections.
#pragma once

#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"
#include "integrands/parallel_geometry.h"

namespace pcbench {

class Blocker : public parallel::FlatlandInterval {
 public:
  static std::vector<ParamSpec> params();
  explicit Blocker(const ResolvedParams& params);
  Reference reference() const;

  double f(const double* x, const double* y) const {
    return crosses_interval(x, y) ? 0.0 : approximate_importance(x, y);
  }
};

}  // namespace pcbench
