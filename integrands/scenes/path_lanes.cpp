#include "integrands/scenes/path_lanes.h"

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
    buffers.next.clear();
    for (std::size_t k = 0; k < n; ++k) {
      WalkLane& lane = lanes[active[k]];
      if (buffers.found[k] && walk_step(scene, *lane.rng, buffers.hits[k], *lane.path, lane.walk)) {
        buffers.next.push_back(active[k]);
      }
    }
    active.swap(buffers.next);
  }
}

}  // namespace pcbench::scene
