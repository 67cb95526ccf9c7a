// restir on scenes: ris (ris.h) whose reservoirs at the first camera vertex are reused across
// pixels within a radius, one or more rounds (restir.cpp). Its row is estimators/restir.cpp; the
// scene reuse controls (ctl_scene_naive_reuse.cpp, ctl_scene_reuse_unshadowed.cpp) are this with
// one mistake each.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "estimators/registry.h"
#include "estimators/reuse_weights.h"
#include "estimators/scene/ris.h"

namespace pcbench::scene {

struct SceneRestirConfig {
  SceneRisConfig ris = {};
  std::uint32_t neighbours = 4;  // N: pixels drawn in the disk per reuse
  std::uint32_t radius = 10;     // of the disk, in pixels
  std::uint32_t rounds = 2;
  ReuseWeighting weighting = {};
  // The control ctl-scene-reuse-unshadowed's mistake: the reuse weights from every source's
  // target without visibility, while the reservoirs' targets (target=visible) see it.
  bool weights_without_visibility = false;
};

std::shared_ptr<const SceneEstimator> make_scene_restir(const SceneRestirConfig& config);

}  // namespace pcbench::scene

namespace pcbench {

// N, radius, rounds and weights on scenes; read_scene_restir_params reads them and ris's.
ParamSpec reuse_neighbours_spec();
ParamSpec reuse_radius_spec();
ParamSpec reuse_rounds_spec();
void read_scene_restir_params(const ResolvedParams& params, scene::SceneRestirConfig& config);

SceneForm restir_scene_form();

// What the scene reuse controls (ctl_scene_naive_reuse.cpp, ctl_scene_reuse_unshadowed.cpp) start
// from: restir with visible targets, so that pixels on either side of a shadow edge hold
// reservoirs of different supports; the parameters they keep (M, N, radius), read from `params`;
// and their declared workload, cornell's blocks' shadows on the floor (64×64, 8 spp × 16
// replicates, against pt).
scene::SceneRestirConfig reuse_control_config(const ResolvedParams& params);
std::vector<ParamSpec> reuse_control_params();
DeclaredWorkload reuse_control_workload();

}  // namespace pcbench
