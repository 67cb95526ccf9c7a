#include "integrands/scenes/render_services.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <optional>

#include "integrands/scenes/strategy_tally.h"

namespace pcbench::scene {
namespace {

// Light subpaths per chunk of parallel work; splats are merged chunk by chunk in order.
constexpr std::uint32_t kLightChunk = 64;

struct Splat {
  std::uint32_t pixel = 0;
  std::uint32_t s = 0;  // light vertices of the splatted prefix (strategy (s, 1))
  Rgb value = {};
};

void add(Image& image, std::uint32_t pixel, const Rgb& v) {
  image.values[3 * std::size_t{pixel} + 0] += v.r;
  image.values[3 * std::size_t{pixel} + 1] += v.g;
  image.values[3 * std::size_t{pixel} + 2] += v.b;
}

PathVertex camera_start(const Scene& scene) {
  PathVertex y0;
  y0.kind = VertexKind::kCamera;
  y0.position = scene.camera().position();
  y0.beta = {1.0, 1.0, 1.0};
  return y0;
}

}  // namespace

std::vector<LightVertexRef> light_vertices(const LightPool& pool) {
  std::vector<LightVertexRef> vertices;
  for (std::uint32_t j = 0; j < pool.paths.size(); ++j) {
    for (std::uint32_t s = 1; s <= pool.paths[j].size(); ++s) vertices.push_back({j, s});
  }
  return vertices;
}

RenderServices::RenderServices(const Scene& scene, const StrategyCounts& counts, std::uint64_t key,
                               std::uint32_t replicate, StrategyTally* strategies)
    : scene_(scene),
      counts_(counts),
      key_(key),
      replicate_(replicate),
      width_(scene.description().width),
      height_(scene.description().height),
      max_length_(scene.description().max_length),
      strategies_(strategies) {}

StreamId RenderServices::stream(StreamPurpose purpose, std::uint32_t sample,
                                std::uint32_t path) const {
  return {.key = key_, .replicate = replicate_, .purpose = purpose, .sample = sample, .path = path};
}

LightPool RenderServices::trace_pool(std::uint32_t index, std::uint32_t m,
                                     TraceCounters& counters) const {
  LightPool pool;
  pool.paths.resize(m);
  const std::uint32_t chunks = (m + kLightChunk - 1) / kLightChunk;
  std::vector<TraceCounters> chunk_counters(chunks);
  tbb::parallel_for(std::uint32_t{0}, chunks, [&](std::uint32_t c) {
    for (std::uint32_t j = c * kLightChunk; j < std::min(m, (c + 1) * kLightChunk); ++j) {
      RandomStream rng(stream(StreamPurpose::kLightPool, index, j));
      trace_light_path(scene_, rng, max_length_, pool.paths[j], chunk_counters[c]);
    }
  });
  for (const TraceCounters& c : chunk_counters) counters.add(c);
  return pool;
}

void RenderServices::splat(const LightPool& pool, Image& sum, TraceCounters& counters) const {
  const std::uint32_t m = static_cast<std::uint32_t>(pool.paths.size());
  const std::uint32_t chunks = (m + kLightChunk - 1) / kLightChunk;
  std::vector<std::vector<Splat>> splats(chunks);
  std::vector<TraceCounters> chunk_counters(chunks);
  const PathVertex camera_vertex = camera_start(scene_);
  tbb::parallel_for(std::uint32_t{0}, chunks, [&](std::uint32_t c) {
    for (std::uint32_t j = c * kLightChunk; j < std::min(m, (c + 1) * kLightChunk); ++j) {
      const Subpath& path = pool.paths[j];
      for (std::uint32_t s = 1; s <= path.size() && s <= max_length_; ++s) {
        std::optional<PixelPosition> pixel;
        const Rgb v = scene::connect(scene_, std::span(path).first(s), std::span(&camera_vertex, 1),
                                     counts_, {}, chunk_counters[c], &pixel);
        if (!pixel || v.is_black()) continue;
        ++chunk_counters[c].splats;
        splats[c].push_back({pixel->y * width_ + pixel->x, s, v / m});
      }
    }
  });
  // In chunk order, so the sums do not depend on the thread count.
  for (std::uint32_t c = 0; c < chunks; ++c) {
    counters.add(chunk_counters[c]);
    for (const Splat& s : splats[c]) {
      add(sum, s.pixel, s.value);
      record(s.s, 1, s.pixel, s.value);
    }
  }
}

void RenderServices::camera_pass(std::uint32_t index, Image& sum, TraceCounters& counters,
                                 const PrefixVisitor& each) const {
  std::vector<TraceCounters> row_counters(height_);
  tbb::parallel_for(std::uint32_t{0}, height_, [&](std::uint32_t y) {
    Subpath camera;
    for (std::uint32_t x = 0; x < width_; ++x) {
      const std::uint32_t pixel = y * width_ + x;
      RandomStream rng(stream(StreamPurpose::kCameraPath, index, pixel));
      const double fx = x + rng.uniform(), fy = y + rng.uniform();
      trace_camera_path(scene_, fx, fy, rng, max_length_, camera, row_counters[y]);
      RandomStream draws(stream(StreamPurpose::kResampling, index, pixel));
      Rgb value;
      for (std::uint32_t t = 2; t <= camera.size(); ++t) {
        CameraPrefix prefix{.pixel = pixel,
                            .vertices = std::span<const PathVertex>(camera).first(t),
                            .max_s = t <= max_length_ ? max_length_ + 1 - t : 0,
                            .camera = rng,
                            .draws = draws,
                            .counters = row_counters[y]};
        each(prefix, value);
      }
      add(sum, pixel, value);
    }
  });
  for (const TraceCounters& c : row_counters) counters.add(c);
}

Rgb RenderServices::connect(std::span<const PathVertex> light, const CameraPrefix& prefix) const {
  return scene::connect(scene_, light, prefix.vertices, counts_, {}, prefix.counters);
}

Rgb RenderServices::connect(std::span<const PathVertex> light, std::span<const PathVertex> camera,
                            const ConnectOptions& options, TraceCounters& counters) const {
  return scene::connect(scene_, light, camera, counts_, options, counters);
}

void RenderServices::record(std::uint32_t s, const CameraPrefix& prefix, const Rgb& value) const {
  record(s, prefix.t(), prefix.pixel, value);
}

void RenderServices::record(std::uint32_t s, std::uint32_t t, std::uint32_t pixel,
                            const Rgb& value) const {
  if (strategies_ != nullptr) strategies_->add(s, t, pixel, value);
}

Rgb RenderServices::connect_recorded(std::span<const PathVertex> light,
                                     const CameraPrefix& prefix) const {
  const Rgb v = connect(light, prefix);
  record(static_cast<std::uint32_t>(light.size()), prefix, v);
  return v;
}

}  // namespace pcbench::scene
