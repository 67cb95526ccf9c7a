// Analytic integrands over points: x in [0,1]^a (the light side), y in [0,1]^b (the camera side).
//
// An analytic integrand is a small "model" class; PointIntegrand<Model> turns it into an
// Integrand. The model's f is called in a non-virtual loop over all pairs of a batch.
//
// A model provides
//   int light_dims() const; int camera_dims() const;
//   double f(const double* x, const double* y);          // may be non-const (scratch state)
//   Reference reference() const;
// and optionally, for non-uniform sampling densities,
//   double sample_light(RandomStream& rng, double* x) const;   // fills x, returns p(x)
//   double sample_camera(RandomStream& rng, double* y) const;  // fills y, returns p(y)
// with, for each, the density it samples at any point (the pair makes chi-square tests mechanical;
// the harness itself does not call it):
//   double light_pdf(const double* x) const;  double camera_pdf(const double* y) const;
// and a cheap resampling importance (e.g. f without its visibility term), which must be > 0
// wherever f != 0:
//   double approximate_importance(const double* x, const double* y) const;
// Without them a side is sampled uniformly (p = 1) and the importance is |f|. Every workspace gets
// its own copy of the model, so a model with scratch state (a parser with bound variables) is
// thread-safe as long as its copy constructor gives the copy its own state.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

#include "base/params.h"
#include "base/rng.h"
#include "integrands/integrand.h"

namespace pcbench {

// The parameters every point integrand has: light_dims (a) and camera_dims (b).
std::vector<ParamSpec> point_dimension_params();

template <typename Model>
class PointWorkspace final : public PathWorkspace {
 public:
  explicit PointWorkspace(const Model& model)
      : model_(model),
        dims_{static_cast<std::size_t>(model.light_dims()),
              static_cast<std::size_t>(model.camera_dims())} {}

  void clear() override {
    for (Side& side : sides_) {
      side.coords.clear();
      side.pdfs.clear();
    }
  }

  void sample_paths(PathSide which, const StreamId& stream, std::uint32_t first_sample,
                    std::uint32_t sample_count, std::uint32_t paths_per_sample) override {
    Side& side = sides_[index(which)];
    const std::size_t dims = dims_[index(which)];
    const std::size_t added = std::size_t{sample_count} * paths_per_sample;
    const std::size_t old_paths = side.pdfs.size();
    side.coords.resize((old_paths + added) * dims);
    side.pdfs.resize(old_paths + added);
    double* coords = side.coords.data() + old_paths * dims;
    double* pdfs = side.pdfs.data() + old_paths;
    // Every path's stream starts with the block of its first counter: computed for a group of
    // paths at once (SIMD lanes: the generator is most of an analytic sample's cost), then each
    // path draws from its own stream exactly as RandomStream(id) would. Groups are small so that
    // the blocks are still in L1 when read.
    const PhiloxKey key = RandomStream::key_of(stream);
    std::array<PhiloxCounter, kGroup> counters, blocks;
    StreamId id = stream;
    id.sample = first_sample;
    id.path = 0;
    for (std::size_t done = 0; done < added;) {
      const std::size_t group = std::min(kGroup, added - done);
      for (std::size_t g = 0; g < group; ++g) {
        counters[g] = RandomStream::first_counter(id);
        if (++id.path == paths_per_sample) {
          id.path = 0;
          ++id.sample;
        }
      }
      philox4x32_10_many(std::span(counters).first(group), key, std::span(blocks).first(group));
      for (std::size_t g = 0; g < group; ++g, coords += dims, ++pdfs) {
        RandomStream rng(key, counters[g], blocks[g]);
        *pdfs = sample_one(which, rng, coords, dims);
      }
      done += group;
    }
  }

  std::span<const double> pdfs(PathSide which) const override { return sides_[index(which)].pdfs; }

  void add_cache_points(std::uint32_t cells) override {
    Side& camera = sides_[1];
    const std::size_t dims = dims_[1];
    const std::size_t old_paths = camera.pdfs.size();
    camera.coords.resize(2 * old_paths * dims);
    camera.pdfs.resize(2 * old_paths, 1.0);
    for (std::size_t c = 0; c < old_paths * dims; ++c) {
      const double cell = std::min(std::floor(camera.coords[c] * cells), cells - 1.0);
      camera.coords[old_paths * dims + c] = (cell + 0.5) / cells;
    }
  }

  void connect(std::span<const PathPair> pairs, std::span<double> values) override {
    const double* light = sides_[0].coords.data();
    const double* camera = sides_[1].coords.data();
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      values[i] = model_.f(light + pairs[i].light * dims_[0], camera + pairs[i].camera * dims_[1]);
    }
  }

  std::vector<double> coordinates(PathSide which, std::uint32_t path) const override {
    const std::size_t dims = dims_[index(which)];
    const auto first =
        sides_[index(which)].coords.begin() + static_cast<std::ptrdiff_t>(path * dims);
    return std::vector<double>(first, first + static_cast<std::ptrdiff_t>(dims));
  }

  void importance(std::span<const PathPair> pairs, std::span<double> values) override {
    if constexpr (requires(const double* p) { model_.approximate_importance(p, p); }) {
      const double* light = sides_[0].coords.data();
      const double* camera = sides_[1].coords.data();
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        values[i] = model_.approximate_importance(light + pairs[i].light * dims_[0],
                                                  camera + pairs[i].camera * dims_[1]);
      }
    } else {
      PathWorkspace::importance(pairs, values);
    }
  }

 private:
  struct Side {
    std::vector<double> coords;  // path i occupies [i * dims, (i + 1) * dims)
    std::vector<double> pdfs;
  };

  static constexpr std::size_t kGroup = 64;  // paths whose first blocks are computed together

  static std::size_t index(PathSide side) { return side == PathSide::kLight ? 0 : 1; }

  double sample_one(PathSide which, RandomStream& rng, double* out, std::size_t dims) const {
    if (which == PathSide::kLight) {
      if constexpr (requires { model_.sample_light(rng, out); }) {
        return model_.sample_light(rng, out);
      }
    } else {
      if constexpr (requires { model_.sample_camera(rng, out); }) {
        return model_.sample_camera(rng, out);
      }
    }
    for (std::size_t d = 0; d < dims; ++d) out[d] = rng.uniform();
    return 1.0;
  }

  Model model_;
  std::size_t dims_[2];
  Side sides_[2];
};

template <typename Model>
class PointIntegrand final : public Integrand {
 public:
  explicit PointIntegrand(Model model) : model_(std::move(model)) {}

  std::unique_ptr<PathWorkspace> make_workspace() const override {
    return std::make_unique<PointWorkspace<Model>>(model_);
  }
  Reference reference() const override { return model_.reference(); }

  const Model& model() const { return model_; }

 private:
  Model model_;
};

}  // namespace pcbench
