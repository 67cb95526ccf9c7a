// A vector into lane j of three coordinate arrays: how the lanes' kernels (connection_lanes.cpp,
// connection_weight_lanes.cpp) gather vertices, one at a time, into structure-of-arrays form.
#pragma once

#include <cstddef>

#include "integrands/scenes/scene_math.h"

namespace pcbench::scene {

inline void put(double* x, double* y, double* z, std::size_t j, const Vec3& v) {
  x[j] = v.x, y[j] = v.y, z[j] = v.z;
}

}  // namespace pcbench::scene
