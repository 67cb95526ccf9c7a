// K light vertices drawn from an iteration's pool for one camera prefix, each connected and
// weighted by its draw's coefficient: the step the light vertex cache and probabilistic
// connections share (lvc.cpp, pcbpt.cpp). With N_v vertices in a pool of M paths, a uniform draw
// has coefficient N_v / (K M) (vertices drawn, paths counted); a draw from P has 1 / (K M P).
#pragma once

#include <cstdint>
#include <span>

#include "integrands/scenes/connection_queue.h"
#include "integrands/scenes/render_services.h"

namespace pcbench::scene {

// One draw: the index into the pool's vertices and the coefficient of its connection.
struct VertexDraw {
  std::uint32_t index = 0;
  double coefficient = 0.0;
};

// Queues each drawn vertex's connection times its coefficient (ConnectionQueue::connect, which
// adds it to the pixel and records it as drawn when the row is resolved); vertices too deep for
// the prefix (more than prefix.max_s) add nothing.
inline void queue_vertex_draws(const LightPool& pool, std::span<const LightVertexRef> vertices,
                               const CameraPrefix& prefix, std::span<const VertexDraw> drawn,
                               ConnectionQueue& queue) {
  for (const VertexDraw& d : drawn) {
    const LightVertexRef& v = vertices[d.index];
    if (v.count > prefix.max_s) continue;
    queue.connect(light_prefix(pool, v), prefix, d.coefficient);
  }
}

// `draw(prefix.draws)` -> VertexDraw, `count` times, each queued as queue_vertex_draws does.
template <class Draw>
void queue_drawn_vertices(const LightPool& pool, std::span<const LightVertexRef> vertices,
                          CameraPrefix& prefix, std::uint32_t count, Draw&& draw,
                          ConnectionQueue& queue) {
  for (std::uint32_t k = 0; k < count; ++k) {
    const VertexDraw d = draw(prefix.draws);
    queue_vertex_draws(pool, vertices, prefix, std::span(&d, 1), queue);
  }
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
