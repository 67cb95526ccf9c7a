// The light vertex cache (lvc.cpp), configurable for its negative control
// (ctl_scene_lvc_per_vertex.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "base/params.h"
#include "estimators/scene/scene_estimator.h"

namespace pcbench::scene {

struct LvcConfig {
  std::uint32_t light_paths = 1024;  // M
  std::uint32_t draws = 8;           // K
  // The control's mistake: each draw weighted 1 / K, normalised by vertices instead of paths.
  bool per_vertex_normalisation = false;
};

// lvc's scene parameters (M, K), with LvcConfig's defaults.
std::vector<ParamSpec> lvc_params();
// M and K from `p` (resolved against lvc_params()); the rest from `base`.
LvcConfig read_lvc_config(const ResolvedParams& p, LvcConfig base = {});

std::shared_ptr<const SceneEstimator> make_lvc(const LvcConfig& config);

}  // namespace pcbench::scene
