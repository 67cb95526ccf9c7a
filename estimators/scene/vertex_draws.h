// K light vertices drawn from an iteration's pool for one camera prefix, each connected and
// weighted by its draw's coefficient: the step the light vertex cache and probabilistic
// connections share (lvc.cpp, pcbpt.cpp). With N_v vertices in a pool of M paths, a uniform draw
// has coefficient N_v / (K M) (vertices drawn, paths counted); a draw from P has 1 / (K M P).
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>

#include "integrands/scenes/render_services.h"

namespace pcbench::scene {

// One draw: the index into the pool's vertices and the coefficient of its connection.
struct VertexDraw {
  std::uint32_t index = 0;
  double coefficient = 0.0;
};

// Adds each drawn vertex's connection, times its coefficient, to `value` in order; vertices too
// deep for the prefix (more than prefix.max_s) add nothing. Each connection's share is recorded
// as drawn.
inline void connect_vertex_draws(const RenderServices& services, const LightPool& pool,
                                 std::span<const LightVertexRef> vertices, CameraPrefix& prefix,
                                 std::span<const VertexDraw> drawn, Rgb& value) {
  for (const VertexDraw& d : drawn) {
    const LightVertexRef& v = vertices[d.index];
    if (v.count > prefix.max_s) continue;
    const Rgb share = d.coefficient * services.connect(light_prefix(pool, v), prefix);
    value += share;
    services.record(v.count, prefix, share);
  }
}

// The most draws made before their connections (kept on the stack).
inline constexpr std::uint32_t kDrawBatch = 16;

// `draw(prefix.draws)` -> VertexDraw, `count` times, each connected as connect_vertex_draws does.
// The draws are made a batch at a time before their connections (connect uses no random number,
// so the numbers and every sum are as if each draw were connected at once): a guided draw reads
// tables that may miss the cache, and the batch's lookups then overlap instead of each waiting
// behind the previous draw's shadow ray.
template <class Draw>
Rgb connect_drawn_vertices(const RenderServices& services, const LightPool& pool,
                           std::span<const LightVertexRef> vertices, CameraPrefix& prefix,
                           std::uint32_t count, Draw&& draw) {
  VertexDraw batch[kDrawBatch];
  Rgb value;
  for (std::uint32_t first = 0; first < count; first += kDrawBatch) {
    const std::uint32_t size = std::min(kDrawBatch, count - first);
    for (std::uint32_t d = 0; d < size; ++d) batch[d] = draw(prefix.draws);
    connect_vertex_draws(services, pool, vertices, prefix, std::span(batch, size), value);
  }
  return value;
}

// The strategy counts of K vertex draws per camera vertex from a pool of M light paths: K per
// connection strategy, 1 per emitter hit, M for light tracing (the pool splatted).
inline StrategyCounts vertex_draw_counts(std::uint32_t light_paths, std::uint32_t draws) {
  const double m = light_paths;
  const double k = draws;
  return {.emitter_hit = 1.0, .next_event = k, .connection = k, .light_tracing = m};
}

// A uniform draw among `vertices` vertices, each with the same coefficient.
struct UniformVertexDraw {
  std::uint32_t vertices = 0;
  double coefficient = 0.0;

  VertexDraw operator()(RandomStream& rng) const {
    return {rng.uniform_index(vertices), coefficient};
  }
};

// The light vertex cache's draw: uniform, coefficient N_v / (K M).
inline UniformVertexDraw uniform_vertex_draw(std::size_t vertices, std::size_t paths,
                                             std::uint32_t draws) {
  const double k = draws;
  const double m = static_cast<double>(paths);
  return {static_cast<std::uint32_t>(vertices), static_cast<double>(vertices) / (k * m)};
}

}  // namespace pcbench::scene
