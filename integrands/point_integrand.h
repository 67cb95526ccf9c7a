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
#include "base/tally.h"
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
        *pdfs = sample_one(which, key, counters[g], blocks[g], coords, dims);
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

  bool tally_every_path(const StreamId& light, const StreamId& camera, std::uint32_t first_sample,
                        std::uint32_t sample_count, std::uint32_t pool_size, double coefficient,
                        Tally& tally, CompensatedSum& magnitudes) override {
    const PhiloxKey key = RandomStream::key_of(light);
    if (key != RandomStream::key_of(camera)) return false;
    // A sample's streams are its pool's, then its camera path's: their first blocks are computed
    // for a group of samples at once, as sample_paths computes them.
    const std::size_t width = std::size_t{pool_size} + 1;
    const std::size_t group = std::max<std::size_t>(1, kFusedPaths / width);
    fused_.counters.resize(group * width);
    fused_.blocks.resize(group * width);
    fused_.x.resize(dims_[0]);
    fused_.y.resize(dims_[1]);
    StreamId light_id = light;
    StreamId camera_id = camera;
    camera_id.path = 0;
    const std::uint32_t end = first_sample + sample_count;
    for (std::uint32_t start = first_sample; start < end;) {
      const auto samples = static_cast<std::uint32_t>(std::min<std::size_t>(group, end - start));
      PhiloxCounter* first = fused_.counters.data();
      for (std::uint32_t s = start; s < start + samples; ++s) {
        light_id.sample = camera_id.sample = s;
        for (light_id.path = 0; light_id.path < pool_size; ++light_id.path) {
          *first++ = RandomStream::first_counter(light_id);
        }
        *first++ = RandomStream::first_counter(camera_id);
      }
      const std::size_t paths = samples * width;
      philox4x32_10_many(std::span(fused_.counters).first(paths), key,
                         std::span(fused_.blocks).first(paths));
      // One loop samples, connects and tallies, so that the tally's running sums (a chain of
      // dependent divisions) overlap the next sample's work.
      const PhiloxCounter* counter = fused_.counters.data();
      const PhiloxCounter* block = fused_.blocks.data();
      double* const x = fused_.x.data();
      double* const y = fused_.y.data();
      const std::size_t light_dims = dims_[0];
      const std::size_t camera_dims = dims_[1];
      CompensatedSum magnitude_sum = magnitudes;
      if (pool_size == 1) {
        // plain: no pool to loop over.
        tally.add_each(start, samples, [&] {
          const double p_y =
              sample_one(PathSide::kCamera, key, counter[1], block[1], y, camera_dims);
          const double p_x = sample_one(PathSide::kLight, key, counter[0], block[0], x, light_dims);
          counter += 2;
          block += 2;
          const double f = model_.f(x, y);
          double sum = 0.0;
          double magnitude = 0.0;
          if (f != 0.0) add_connection_term(f, coefficient, p_x, p_y, sum, magnitude);
          magnitude_sum.add(magnitude);
          return sum;
        });
      } else {
        tally.add_each(start, samples, [&] {
          const double p_y = sample_one(PathSide::kCamera, key, counter[pool_size],
                                        block[pool_size], y, camera_dims);
          double sum = 0.0;
          double magnitude = 0.0;
          for (std::uint32_t j = 0; j < pool_size; ++j) {
            const double p_x =
                sample_one(PathSide::kLight, key, counter[j], block[j], x, light_dims);
            const double f = model_.f(x, y);
            if (f == 0.0) continue;
            add_connection_term(f, coefficient, p_x, p_y, sum, magnitude);
          }
          counter += width;
          block += width;
          magnitude_sum.add(magnitude);
          return sum;
        });
      }
      magnitudes = magnitude_sum;
      start += samples;
    }
    return true;
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

  // The fused loop's streams (tally_every_path): their first counters and blocks, and one
  // light and one camera point.
  struct Fused {
    std::vector<PhiloxCounter> counters;
    std::vector<PhiloxCounter> blocks;
    std::vector<double> x;
    std::vector<double> y;
  };

  static constexpr std::size_t kGroup = 64;  // paths whose first blocks are computed together
  // The same for the fused loop, which computes a sample's light and camera paths' blocks
  // together: 64 samples of plain.
  static constexpr std::size_t kFusedPaths = 128;

  static std::size_t index(PathSide side) { return side == PathSide::kLight ? 0 : 1; }

  // One path of side `which` into `out`, from the stream of first counter `counter` under `key`
  // whose first block is `block`; returns its density. Uniform sampling takes the stream's
  // uniforms in order: the first two straight from the first block (what the stream would
  // return), so that a path of one or two dimensions needs no stream object.
  double sample_one(PathSide which, const PhiloxKey& key, const PhiloxCounter& counter,
                    const PhiloxCounter& block, double* out, std::size_t dims) const {
    if (which == PathSide::kLight) {
      if constexpr (requires(RandomStream & rng) { model_.sample_light(rng, out); }) {
        RandomStream rng(key, counter, block);
        return model_.sample_light(rng, out);
      }
    } else {
      if constexpr (requires(RandomStream & rng) { model_.sample_camera(rng, out); }) {
        RandomStream rng(key, counter, block);
        return model_.sample_camera(rng, out);
      }
    }
    if (dims > 0) out[0] = RandomStream::uniform_of(block, 0);
    if (dims > 1) out[1] = RandomStream::uniform_of(block, 2);
    if (dims > 2) {
      RandomStream rng(key, counter, block);
      rng.uniform();
      rng.uniform();
      for (std::size_t d = 2; d < dims; ++d) out[d] = rng.uniform();
    }
    return 1.0;
  }

  Model model_;
  std::size_t dims_[2];
  Side sides_[2];
  Fused fused_;
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
