// K light vertices drawn from an iteration's pool for one camera prefix, each connected and
// weighted by its draw's coefficient: the step the light vertex cache and probabilistic
// connections share (lvc.cpp, pcbpt.cpp). With N_v vertices in a pool of M paths, a uniform draw
// has coefficient N_v / (K M) (vertices drawn, paths counted); a draw from P has 1 / (K M P).
#pragma once

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

// `draw(prefix.draws)` -> VertexDraw, `count` times; vertices too deep for the prefix (more than
// prefix.max_s) add nothing. Each connection's share is recorded as drawn.
template <class Draw>
Rgb connect_drawn_vertices(const RenderServices& services, const LightPool& pool,
                           std::span<const LightVertexRef> vertices, CameraPrefix& prefix,
                           std::uint32_t count, Draw&& draw) {
  Rgb value;
  for (std::uint32_t d = 0; d < count; ++d) {
    const VertexDraw drawn_vertex = draw(prefix.draws);
    const LightVertexRef& v = vertices[drawn_vertex.index];
    if (v.count > prefix.max_s) continue;
    const Rgb drawn = drawn_vertex.coefficient * services.connect(light_prefix(pool, v), prefix);
    value += drawn;
    services.record(v.count, prefix, drawn);
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
