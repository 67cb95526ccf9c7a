// The integrand interface: the seed's two-path integral I = ∫_A ∫_B f(x, y) dy dx, with x a light
// (sub)path and y a camera (sub)path.
//
// An integrand samples paths, evaluates the connection value f(x, y) and the resampling
// importance w(x, y), and reports its reference value. Calls are per batch: an estimator asks for
// all the paths of a batch of camera samples at once and for all the connections it needs in
// one call, so that no virtual call sits in a per-sample loop.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "base/rng.h"
#include "base/tally.h"

namespace pcbench {

enum class PathSide { kLight, kCamera };

enum class ReferenceKind { kExact, kNumerical, kRendered, kNone };

const char* to_string(ReferenceKind kind);

struct Reference {
  double value = std::numeric_limits<double>::quiet_NaN();
  ReferenceKind kind = ReferenceKind::kNone;
  double uncertainty = 0.0;                              // standard error of `value` (0 for exact)
  double dof = std::numeric_limits<double>::infinity();  // degrees of freedom of `uncertainty`
  // ∫∫ |f| where known (the value itself for a non-negative integrand): the scale against which
  // a bias counts as small. Unknown (NaN) for signed integrands; then the run's own estimate of
  // ∫∫ |f| stands in, which a biased estimator may bias too.
  double magnitude = std::numeric_limits<double>::quiet_NaN();
};

// A connection between sampled path `light` and sampled path `camera` (indices into the
// workspace's paths of each side, in sampling order).
struct PathPair {
  std::uint32_t light = 0;
  std::uint32_t camera = 0;
};

// One term of a camera sample's estimate, as the family's estimators sum them
// (estimators/resampling.cpp): a connection of value f with coefficient c between paths of
// densities p_x and p_y adds c f / (p_x p_y) to the estimate and c |f| / (p_x p_y) to its
// magnitude (the estimate of ∫∫ |f|). Callers skip terms with f == 0. Written once, so that the
// fused loop of a workspace (PathWorkspace::tally_every_path) and the estimators' sums are the
// same operations, bit for bit.
inline void add_connection_term(double f, double coefficient, double p_x, double p_y, double& sum,
                                double& magnitude) {
  const double weight = coefficient / (p_x * p_y);
  sum += f * weight;
  magnitude += std::fabs(f) * weight;
}

// Per-thread storage of the paths sampled for one batch. Holds no state between batches beyond
// reusable memory, so results do not depend on which thread's workspace serves a batch.
class PathWorkspace {
 public:
  virtual ~PathWorkspace() = default;

  // Forgets all sampled paths (keeps the memory).
  virtual void clear() = 0;

  // For each sample s in [first_sample, first_sample + sample_count) and each j < paths_per_sample,
  // samples one path of `side` from the stream `stream` with .sample = s and .path = j, and
  // appends it: the new path's index is (previous count) + (s - first_sample) * paths_per_sample
  // + j.
  virtual void sample_paths(PathSide side, const StreamId& stream, std::uint32_t first_sample,
                            std::uint32_t sample_count, std::uint32_t paths_per_sample) = 0;

  // Density of each sampled path of `side` with respect to the integration measure, in sampling
  // order: p(x) or p(y) of the seed's Eq. (2).
  virtual std::span<const double> pdfs(PathSide side) const = 0;

  // f(x_light, y_camera) for each pair.
  virtual void connect(std::span<const PathPair> pairs, std::span<double> values) = 0;

  // Resampling importance w(x, y) >= 0 for each pair; it must be > 0 wherever f != 0.
  // Default: |f|.
  virtual void importance(std::span<const PathPair> pairs, std::span<double> values);

  // Appends one camera path per camera path sampled so far (in the same order): its *cache
  // point*, the centre of the cell that holds it in a grid of `cells` cells per dimension.
  // Probabilistic connections cache their importance per screen tile this way: every camera
  // path of a cell is guided by what its cache point sees. The appended paths are for
  // importance only; their pdfs mean nothing. Default: throws std::runtime_error (no cells).
  virtual void add_cache_points(std::uint32_t cells);

  // The coordinates of sampled path `index` of `side`, for `pcbench replay` to print (a
  // debugging aid, never used by an estimate). Default: none known.
  virtual std::vector<double> coordinates(PathSide side, std::uint32_t index) const;

  // Plain and vertex connection on fresh pools in one loop, the runner's fast path: for each
  // camera sample s in [first_sample, first_sample + sample_count) in order, its camera path
  // (from stream `camera` with .sample = s, .path = 0) and its `pool_size` light paths (from
  // stream `light` with .sample = s, .path = j), each light path connected once; the estimate
  // Σ_j of add_connection_term(f(x_j, y), coefficient, p(x_j), p(y)) over the f != 0 (from 0, in
  // j order) goes to `tally` as sample s and its magnitude to `magnitudes`. These are the numbers
  // that sample_paths, connect and the estimator's sums give, without storing any path; the
  // workspace's sampled paths are left as they were. `light` and `camera` must share their key.
  // Returns false, having done nothing, where the workspace has no such loop (the default).
  virtual bool tally_every_path(const StreamId& light, const StreamId& camera,
                                std::uint32_t first_sample, std::uint32_t sample_count,
                                std::uint32_t pool_size, double coefficient, Tally& tally,
                                CompensatedSum& magnitudes);
};

class Integrand {
 public:
  virtual ~Integrand() = default;

  // A fresh workspace for one thread.
  virtual std::unique_ptr<PathWorkspace> make_workspace() const = 0;

  virtual Reference reference() const = 0;
};

}  // namespace pcbench
