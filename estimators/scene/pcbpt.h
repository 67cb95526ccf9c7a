// Probabilistic connections (pcbpt.cpp), configurable for its ablations and its negative control
// (ctl_scene_visible_only.cpp). The defaults are the published design except four that are
// pcbench's own, on measurement (docs/guide/scenes.md, "pcbpt's parameters"): nee=fresh,
// K = 8, M = 128 and light_tracing=M, where the published design has nee=draws, K = 3, a larger
// pool (1024 here before) and light_tracing=pixels. The comments name the legacy value of each
// choice (the tile design pcbench had before: cache=tile-first-hit, lookup=tile,
// cache_importance=connection, visibility=ignored, light_tracing=M, nee=draws, M=1024, K=8,
// uniform_mix=0.1, mis=balance), which reproduces that estimator bit for bit.
#pragma once

#include <cstdint>
#include <memory>

#include "estimators/scene/scene_estimator.h"

namespace pcbench::scene {

struct PcbptConfig {
  // M: light paths whose vertices are the connections' candidates (published design and legacy
  // 1024 here).
  std::uint32_t light_paths = 128;
  // Light tracing (t = 1) from W·H paths as BDPT splats (the pool is max(M, W·H) and its first
  // M paths are the candidates: the published design), or from the M candidates only (legacy,
  // and pcbench's default on measurement).
  bool light_tracing_pixels = false;
  std::uint32_t draws = 8;    // K per camera vertex (published 3, legacy 8)
  double uniform_mix = 0.25;  // u, the defensive uniform share (legacy 0.1)
  // Cache points at every non-specular depth of cache paths from a grid of `grid` × `grid`
  // pixel blocks, or one per `tile` × `tile` tile at the first hit (legacy).
  bool every_depth = true;
  std::uint32_t grid = 16;
  std::uint32_t tile = 8;
  // Next-event estimation (s = 1): every camera vertex connects to an emitter vertex drawn for
  // it alone, as path tracing does, and the K draws choose among the pool's vertices with s >= 2
  // (nee=fresh), or the pool's emitter vertices are candidates of the draws like every other
  // vertex (nee=draws: the published design, and legacy).
  bool nee_fresh = true;
  // A camera vertex draws from the mixture of its `nearest` nearest cache points (kd-tree) and
  // the uniform share (kNearest), or from its block's cache point at its own depth (kTile,
  // legacy), or is its own cache point (kExact: the importance of every candidate weighed at the
  // camera vertex itself, shadow rays included: the limit of a dense cache, O(N_v) per camera
  // vertex, for measuring what guidance can buy, not for rendering).
  enum class Lookup { kNearest, kTile, kExact };
  Lookup lookup = Lookup::kNearest;
  bool nearest_lookup() const { return lookup == Lookup::kNearest; }
  std::uint32_t nearest = 3;  // Nc
  // lookup=tile: a vertex deeper than its block's cache points draws from the first hit's P
  // (guide=all), or uniformly (guide=first, legacy).
  bool guide_all = false;
  // Importance of light vertex x at cache point y: x's throughput × its BSDF (or emission)
  // towards y × G(x, y), without the camera side (kLight), or the whole unweighted connection
  // value through the cache path (kConnection, legacy), or that value with the connection's MIS
  // weight (kWeighted: what the connection would add to the cache path's pixel).
  enum class Importance { kLight, kConnection, kWeighted };
  Importance importance = Importance::kLight;
  // Visibility of x from y in the importance (one shadow ray per cache point and light vertex):
  // an occluded entry is scaled by `floor` (0: exact, only the uniform share keeps its support).
  bool cache_visibility = true;
  double visibility_floor = 0.02;
  // MIS counts of the connection strategies: K each (mis=balance, legacy), or the resampled
  // draws' effective samples of the path's light vertex (mis=resampling, resampling_counts.h).
  bool resampling_mis = false;
  // The control's mistake with it: a tile whose cache point sees no light vertex draws nothing
  // (with u = 0 its P is all zero), although its other pixels may see some.
  bool unseen_tiles_draw_nothing = false;
};

std::shared_ptr<const SceneEstimator> make_pcbpt(const PcbptConfig& config);

}  // namespace pcbench::scene
