#include "integrands/scenes/render_services.h"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <optional>

#include "integrands/scenes/path_lanes.h"
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

struct RenderServices::CameraRow {
  std::vector<Subpath> paths;
  std::vector<RandomStream> streams;
  std::vector<WalkLane> lanes;
  LaneBuffers buffers;
  ConnectionQueue queue;
};

namespace {

// A chunk of light paths' lanes (trace_pool).
struct LightLanes {
  std::vector<RandomStream> streams;
  std::vector<WalkLane> lanes;
  LaneBuffers buffers;
};

// A chunk of light paths' connections to the camera (splat).
struct SplatBatch {
  std::vector<ConnectionPair> pairs;
  std::vector<std::uint32_t> strategy;
  std::vector<Rgb> values;
  std::vector<std::optional<PixelPosition>> pixels;
  ConnectionBatch batch;
};

}  // namespace

struct RenderServices::Scratch {
  tbb::enumerable_thread_specific<CameraRow> rows;
  tbb::enumerable_thread_specific<LightLanes> light_lanes;
  tbb::enumerable_thread_specific<SplatBatch> splat_batches;
  // Each chunk's splats, kept from one iteration to the next: allocating and growing a few
  // hundred vectors anew every iteration was 2.3% of BDPT's run on cornell at 128×128 (perf:
  // malloc and the page faults it took).
  std::vector<std::vector<Splat>> splats;
};

RenderServices::RenderServices(const Scene& scene, const StrategyCounts& counts, std::uint64_t key,
                               std::uint32_t replicate, StrategyTally* strategies)
    : scene_(scene),
      counts_(counts),
      key_(key),
      replicate_(replicate),
      width_(scene.description().width),
      height_(scene.description().height),
      max_length_(scene.description().max_length),
      strategies_(strategies),
      scratch_(std::make_unique<Scratch>()) {}

RenderServices::~RenderServices() = default;

StreamId RenderServices::stream(StreamPurpose purpose, std::uint32_t sample,
                                std::uint32_t path) const {
  return {.key = key_, .replicate = replicate_, .purpose = purpose, .sample = sample, .path = path};
}

void RenderServices::trace_pool(std::uint32_t index, std::uint32_t m, LightPool& pool,
                                TraceCounters& counters) const {
  pool.paths.resize(m);
  const std::uint32_t chunks = (m + kLightChunk - 1) / kLightChunk;
  std::vector<TraceCounters> chunk_counters(chunks);
  tbb::parallel_for(std::uint32_t{0}, chunks, [&](std::uint32_t c) {
    // The chunk's paths walked in lanes (path_lanes.h), each from its own stream.
    LightLanes& lanes = scratch_->light_lanes.local();
    const std::uint32_t first = c * kLightChunk, end = std::min(m, (c + 1) * kLightChunk);
    lanes.streams.clear();
    lanes.streams.reserve(end - first);
    lanes.lanes.clear();
    for (std::uint32_t j = first; j < end; ++j) {
      RandomStream& rng = lanes.streams.emplace_back(stream(StreamPurpose::kLightPool, index, j));
      rng.read_ahead();  // a walk reads two uniforms a bounce
      std::optional<Walk> walk =
          start_light_path(scene_, rng, max_length_, pool.paths[j], chunk_counters[c]);
      if (walk) lanes.lanes.push_back({*walk, &rng, &pool.paths[j]});
    }
    walk_lanes(scene_, lanes.lanes, lanes.buffers, chunk_counters[c].light_rays);
    for (std::uint32_t j = first; j < end; ++j) store_light_weight_sums(pool.paths[j], counts_);
  });
  for (const TraceCounters& c : chunk_counters) counters.add(c);
}

void RenderServices::splat(const LightPool& pool, Image& sum, TraceCounters& counters) const {
  const std::uint32_t m = static_cast<std::uint32_t>(pool.paths.size());
  const std::uint32_t chunks = (m + kLightChunk - 1) / kLightChunk;
  std::vector<std::vector<Splat>>& splats = scratch_->splats;
  splats.resize(chunks);
  for (std::vector<Splat>& chunk : splats) chunk.clear();
  std::vector<TraceCounters> chunk_counters(chunks);
  const PathVertex camera_vertex = camera_start(scene_);
  tbb::parallel_for(std::uint32_t{0}, chunks, [&](std::uint32_t c) {
    // The chunk's connections to the camera as one batch, their shadow rays in packets.
    SplatBatch& b = scratch_->splat_batches.local();
    b.pairs.clear();
    b.strategy.clear();
    for (std::uint32_t j = c * kLightChunk; j < std::min(m, (c + 1) * kLightChunk); ++j) {
      const Subpath& path = pool.paths[j];
      for (std::uint32_t s = 1; s <= path.size() && s <= max_length_; ++s) {
        b.pairs.push_back({std::span(path).first(s), std::span(&camera_vertex, 1)});
        b.strategy.push_back(s);
      }
    }
    b.values.resize(b.pairs.size());
    b.pixels.assign(b.pairs.size(), std::nullopt);
    b.batch.connect_all(scene_, counts_, b.pairs, b.values, chunk_counters[c], b.pixels);
    for (std::size_t i = 0; i < b.pairs.size(); ++i) {
      const std::optional<PixelPosition>& pixel = b.pixels[i];
      if (!pixel || b.values[i].is_black()) continue;
      ++chunk_counters[c].splats;
      splats[c].push_back({pixel->y * width_ + pixel->x, b.strategy[i], b.values[i] / m});
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

namespace {

// For every pixel of row y in order, each prefix y_0 .. y_{t-1}, t = 2, 3, … of its walked
// camera subpath (`on_prefix`), with the pixel's camera stream and a fresh resampling stream;
// then `after_pixel(pixel)`.
template <typename OnPrefix, typename AfterPixel>
void for_each_prefix(const RenderServices& services, std::uint32_t index, std::uint32_t y,
                     std::span<const Subpath> paths, std::span<RandomStream> streams,
                     TraceCounters& counters, OnPrefix&& on_prefix, AfterPixel&& after_pixel) {
  const std::uint32_t width = services.width(), max_length = services.max_length();
  for (std::uint32_t x = 0; x < width; ++x) {
    const std::uint32_t pixel = y * width + x;
    const Subpath& camera = paths[x];
    RandomStream draws(services.stream(StreamPurpose::kResampling, index, pixel));
    draws.read_ahead();  // K draws at every camera vertex (pcbpt, lvc), when the pass draws
    for (std::uint32_t t = 2; t <= camera.size(); ++t) {
      CameraPrefix prefix{.pixel = pixel,
                          .vertices = std::span<const PathVertex>(camera).first(t),
                          .max_s = t <= max_length ? max_length + 1 - t : 0,
                          .camera = streams[x],
                          .draws = draws,
                          .counters = counters};
      on_prefix(prefix);
    }
    after_pixel(pixel);
  }
}

}  // namespace

void RenderServices::walk_camera_row(std::uint32_t index, std::uint32_t y, CameraRow& row,
                                     TraceCounters& counters) const {
  row.paths.resize(width_);
  row.streams.clear();
  row.streams.reserve(width_);
  row.lanes.clear();
  for (std::uint32_t x = 0; x < width_; ++x) {
    RandomStream& rng =
        row.streams.emplace_back(stream(StreamPurpose::kCameraPath, index, y * width_ + x));
    rng.read_ahead();  // the walk's two uniforms a bounce, then next-event estimation's
    const double fx = x + rng.uniform(), fy = y + rng.uniform();
    const Walk walk = start_camera_path(scene_, fx, fy, max_length_, row.paths[x]);
    row.lanes.push_back({walk, &rng, &row.paths[x]});
  }
  walk_lanes(scene_, row.lanes, row.buffers, counters.camera_rays);
  for (Subpath& path : row.paths) store_camera_weight_sums(path, counts_);
}

void RenderServices::camera_pass(std::uint32_t index, Image& sum, TraceCounters& counters,
                                 const PrefixVisitor& each) const {
  std::vector<TraceCounters> row_counters(height_);
  tbb::parallel_for(std::uint32_t{0}, height_, [&](std::uint32_t y) {
    CameraRow& row = scratch_->rows.local();
    walk_camera_row(index, y, row, row_counters[y]);
    Rgb value;
    for_each_prefix(
        *this, index, y, row.paths, row.streams, row_counters[y],
        [&](CameraPrefix& prefix) { each(prefix, value); },
        [&](std::uint32_t pixel) {
          add(sum, pixel, value);
          value = {};
        });
  });
  for (const TraceCounters& c : row_counters) counters.add(c);
}

void RenderServices::camera_pass_queued(std::uint32_t index, Image& sum, TraceCounters& counters,
                                        bool emitter_hits, const QueueingVisitor& each) const {
  std::vector<TraceCounters> row_counters(height_);
  tbb::parallel_for(std::uint32_t{0}, height_, [&](std::uint32_t y) {
    CameraRow& row = scratch_->rows.local();
    walk_camera_row(index, y, row, row_counters[y]);
    ConnectionQueue& queue = row.queue;
    queue.clear();
    for_each_prefix(
        *this, index, y, row.paths, row.streams, row_counters[y],
        [&](CameraPrefix& prefix) {
          const Rgb hit = emitter_hits ? connect_recorded({}, prefix) : Rgb{};
          queue.begin_prefix(prefix, emitter_hits, hit);
          if (prefix.max_s > 0) each(prefix, queue);
        },
        [](std::uint32_t) {});
    queue.resolve(scene_, counts_, row_counters[y]);
    // Each pixel's prefixes are consecutive, in order of t.
    Rgb value;
    std::uint32_t pixel = y * width_;
    for (const ConnectionQueue::Prefix& p : queue.prefixes()) {
      for (; pixel < p.pixel; ++pixel) {
        add(sum, pixel, value);
        value = {};
      }
      if (p.adds_emitter_hit) value += p.emitter_hit;
      if (!p.connects) continue;
      for (std::uint32_t i = p.first; i < p.end; ++i) {
        record(queue.strategy(i), static_cast<std::uint32_t>(p.camera.size()), p.pixel,
               queue.value(i));
      }
      value += queue.sum(p);
    }
    for (; pixel < (y + 1) * width_; ++pixel) {
      add(sum, pixel, value);
      value = {};
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
