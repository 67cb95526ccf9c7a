// Many subpaths walked in lockstep: each round traces the next ray of every walk still going as
// Embree packets (Scene::intersect_many), then takes each walk's step (walk_step, path_vertex.h)
// in lane order. Walks that end drop out and the rest are compacted, so every packet but the
// last of a round is full. Each walk draws from its own stream in the order it would alone, and
// the step is the one-ray walk's step, so a path is the same as trace_camera_path or
// trace_light_path make it; only the order in which rays reach Embree changes.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "base/rng.h"
#include "integrands/scenes/path_vertex.h"

namespace pcbench::scene {

// One walk in a lane: its state, its stream and the path it extends.
struct WalkLane {
  Walk walk;
  RandomStream* rng = nullptr;
  std::vector<PathVertex>* path = nullptr;
};

// Reused buffers of walk_lanes, one per thread (the rays and hits of a round).
struct LaneBuffers {
  std::vector<std::uint32_t> active, next;
  std::vector<Vec3> origins, directions;
  std::vector<Hit> hits;
  std::vector<std::uint8_t> found;
};

// Walks every lane to its end; counts the closest-hit rays in `rays`.
void walk_lanes(const Scene& scene, std::span<WalkLane> lanes, LaneBuffers& buffers,
                std::uint64_t& rays);

}  // namespace pcbench::scene
