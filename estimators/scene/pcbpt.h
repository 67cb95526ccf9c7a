// Probabilistic connections (pcbpt.cpp), configurable for its negative control
// (ctl_scene_visible_only.cpp).
#pragma once

#include <cstdint>
#include <memory>

#include "estimators/scene/scene_estimator.h"

namespace pcbench::scene {

struct PcbptConfig {
  std::uint32_t light_paths = 1024;  // M
  std::uint32_t draws = 8;           // K per camera vertex
  double uniform_mix = 0.1;          // u
  std::uint32_t tile = 8;            // pixels per side of a cache tile
  // Guide every camera vertex by its tile's cache point, not just the first one (the cache
  // point is a first hit; deeper vertices are elsewhere and are drawn uniformly).
  bool guide_all = false;
  // The importance at the cache point includes its visibility to the light vertex (one shadow
  // ray per tile and light vertex). Light blocked at the cache point may still reach other
  // pixels of the tile, so this is unbiased only with uniform_mix > 0, which pcbpt's parameters
  // require; without mixing it is the negative control.
  bool cache_visibility = false;
  // The control's mistake with it: a tile whose cache point sees no light vertex draws nothing
  // (with u = 0 its P is all zero), although its other pixels may see some.
  bool unseen_tiles_draw_nothing = false;
};

std::shared_ptr<const SceneEstimator> make_pcbpt(const PcbptConfig& config);

}  // namespace pcbench::scene
