// Many subpaths walked in lockstep: each round traces the next ray of every walk still going as
// Embree packets (Scene::intersect_many), then takes each walk's step (walk_step, path_vertex.h)
// in two halves: every lane adds its vertex and draws its step's two uniforms (walk_arrive),
// the round's azimuths are computed together in SIMD lanes (cos_sin_of_turns: scalar, their
// series' chain of dependent multiplications was most of a step's sampling), then every lane
// samples its next direction (walk_scatter; those on Lambertian surfaces together in SIMD lanes,
// scatter_lanes.h). Walks that end drop out and the rest are
// compacted, so every packet but the last of a round is full. Each walk draws from its own
// stream in the order it would alone, and the halves are the one-ray walk's step, so a path is
// the same as trace_camera_path or trace_light_path make it, to the bit; only the order in which
// rays reach Embree changes.
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

// Reused buffers of walk_lanes, one per thread (the rays, hits and samples of a round).
struct LaneBuffers {
  std::vector<std::uint32_t> active, next;
  std::vector<Vec3> origins, directions;
  std::vector<Hit> hits;
  std::vector<std::uint8_t> found;
  std::vector<std::uint32_t> scattering;  // the round's lanes that sample a next direction
  std::vector<double> u1, u2, cos, sin;   // their uniforms and azimuths
  std::vector<std::uint8_t> goes;         // whether each of them goes on
  std::vector<std::uint32_t> lambertian;  // those on Lambertian surfaces: indices into scattering
};

// Walks every lane to its end; counts the closest-hit rays in `rays`.
void walk_lanes(const Scene& scene, std::span<WalkLane> lanes, LaneBuffers& buffers,
                std::uint64_t& rays);

}  // namespace pcbench::scene
