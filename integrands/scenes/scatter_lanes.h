// The scatter half of a round of walks (walk_scatter, path_vertex.h) for the lanes whose vertex
// is on a Lambertian surface, computed together in SIMD lanes: the facing normal and its frame,
// the cosine-weighted direction, f and both densities, the throughput's update and the reverse
// density of the vertex before. Until then they were 10% of path tracing's time, one lane at a
// time (docs/findings/lanes.md). In walk_scatter's order of operations, without fused
// multiply-adds (the file is built without contraction: CMakeLists.txt) and with IEEE's exact
// roots and quotients, so every walk is the one walk_scatter makes, to the bit
// (ScenePackets.*; ctest estimators.hashes).
#pragma once

#include <cstddef>
#include <span>

#include "integrands/scenes/path_lanes.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {

// For each j of buffers.lambertian, a scattering lane of the round (walk_lanes, path_lanes.cpp)
// whose vertex is on a Lambertian surface (MaterialKind::kDiffuse), with k = scattering[j]:
//     goes[j] = walk_scatter(scene, hits[k], u1[j], {cos[j], sin[j]}, lane's path, lane's walk)
// for the lane lanes[active[k]] (goes, hits, u1, cos, sin, scattering, active: the buffers').
void scatter_lambertian(const Scene& scene, std::span<WalkLane> lanes, LaneBuffers& buffers);

}  // namespace pcbench::scene
