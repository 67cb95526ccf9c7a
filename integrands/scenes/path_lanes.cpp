#include "integrands/scenes/path_lanes.h"

#include "integrands/scenes/scatter_lanes.h"
#include "integrands/scenes/turn_trig.h"

namespace pcbench::scene {

void walk_lanes(const Scene& scene, std::span<WalkLane> lanes, LaneBuffers& buffers,
                std::uint64_t& rays) {
  std::vector<std::uint32_t>& active = buffers.active;
  active.clear();
  for (std::uint32_t i = 0; i < lanes.size(); ++i) {
    if (lanes[i].path->size() < lanes[i].walk.max_vertices) active.push_back(i);
  }
  while (!active.empty()) {
    const std::size_t n = active.size();
    buffers.origins.resize(n);
    buffers.directions.resize(n);
    buffers.hits.resize(n);
    buffers.found.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const WalkLane& lane = lanes[active[k]];
      buffers.origins[k] = lane.path->back().position;
      buffers.directions[k] = lane.walk.direction;
    }
    rays += n;
    scene.intersect_many(buffers.origins, buffers.directions, buffers.hits, buffers.found);
    // walk_step for each lane, in two halves around the round's azimuths (see the header).
    std::vector<std::uint32_t>& scattering = buffers.scattering;
    scattering.clear();
    buffers.u1.resize(n);
    buffers.u2.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      WalkLane& lane = lanes[active[k]];
      if (!buffers.found[k] || !walk_arrive(scene, buffers.hits[k], *lane.path, lane.walk))
        continue;
      buffers.u1[scattering.size()] = lane.rng->uniform();
      buffers.u2[scattering.size()] = lane.rng->uniform();
      scattering.push_back(static_cast<std::uint32_t>(k));
    }
    const std::size_t m = scattering.size();
    buffers.cos.resize(m);
    buffers.sin.resize(m);
    cos_sin_of_turns(std::span(buffers.u2).first(m), buffers.cos, buffers.sin);
    // The lanes on Lambertian surfaces scatter together, in SIMD lanes; the others one by one.
    buffers.goes.resize(m);
    buffers.lambertian.clear();
    for (std::size_t j = 0; j < m; ++j) {
      const std::uint32_t k = scattering[j];
      if (scene.material(buffers.hits[k].triangle).kind == MaterialKind::kDiffuse) {
        buffers.lambertian.push_back(static_cast<std::uint32_t>(j));
        continue;
      }
      WalkLane& lane = lanes[active[k]];
      buffers.goes[j] = walk_scatter(scene, buffers.hits[k], buffers.u1[j],
                                     {buffers.cos[j], buffers.sin[j]}, *lane.path, lane.walk);
    }
    scatter_lambertian(scene, lanes, buffers);
    buffers.next.clear();
    for (std::size_t j = 0; j < m; ++j) {
      if (buffers.goes[j]) buffers.next.push_back(active[scattering[j]]);
    }
    active.swap(buffers.next);
  }
}

}  // namespace pcbench::scene
