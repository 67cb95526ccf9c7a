// Probabilistic connections (pcbpt.cpp), configurable for its ablations, and with one flaw for
// its negative control (ctl_scene_visible_only.cpp). The defaults are pcbpt's: the published design
// but for four choices that are pcbench's own, on measurement (docs/guide/scenes.md, "pcbpt's
// parameters"). Two named configurations, each defined once below as parameters over the defaults,
// name the designs the others are measured against; `pcbench list` shows them.
#pragma once

#include <cstdint>
#include <memory>

#include "base/params.h"
#include "estimators/scene/scene_estimator.h"

namespace pcbench::scene {

// The published design (Popov et al. 2015, with the choices public sources make where the paper
// leaves them open): the four choices where pcbench's defaults differ. Its runs keep the ids and
// numbers they had when it was pcbpt's default.
const ParamText& pcbpt_published_design();
// The tile design pcbench had before the published one, bit for bit (same run ids and numbers):
// one cache point per tile at the first hit, its P, over the whole connection value with
// visibility ignored, mixed with uniform, deeper vertices uniform (guide=first); the pool and
// draws it had.
const ParamText& pcbpt_legacy_tile_design();

struct PcbptConfig {
  // M: light paths whose vertices are the connections' candidates.
  std::uint32_t light_paths = 128;
  // Light tracing (t = 1) from W·H paths as BDPT splats (the pool is max(M, W·H) and its first
  // M paths are the candidates), or from the M candidates only.
  bool light_tracing_pixels = false;
  std::uint32_t draws = 8;    // K per camera vertex
  double uniform_mix = 0.25;  // u, the defensive uniform share
  // Cache points at every non-specular depth of cache paths from a grid of `grid` × `grid`
  // pixel blocks, or one per `tile` × `tile` tile at the first hit.
  bool every_depth = true;
  std::uint32_t grid = 16;
  std::uint32_t tile = 8;
  // Next-event estimation (s = 1): every camera vertex connects to an emitter vertex drawn for
  // it alone, as path tracing does, and the K draws choose among the pool's vertices with s >= 2
  // (nee=fresh), or the pool's emitter vertices are candidates of the draws like every other
  // vertex (nee=draws).
  bool nee_fresh = true;
  // A camera vertex draws from the mixture of its `nearest` nearest cache points (kd-tree) and
  // the uniform share (kNearest), or from its block's cache point at its own depth (kTile), or
  // is its own cache point (kExact: the importance of every candidate weighed at the
  // camera vertex itself, shadow rays included: the limit of a dense cache, O(N_v) per camera
  // vertex, for measuring what guidance can buy, not for rendering).
  enum class Lookup { kNearest, kTile, kExact };
  Lookup lookup = Lookup::kNearest;
  bool nearest_lookup() const { return lookup == Lookup::kNearest; }
  std::uint32_t nearest = 3;  // Nc
  // lookup=tile: a vertex deeper than its block's cache points draws from the first hit's P
  // (guide=all), or uniformly (guide=first).
  bool guide_all = false;
  // Importance of light vertex x at cache point y: x's throughput × its BSDF (or emission)
  // towards y × G(x, y), without the camera side (kLight), or the whole unweighted connection
  // value through the cache path (kConnection), or that value with the connection's MIS
  // weight (kWeighted: what the connection would add to the cache path's pixel).
  enum class Importance { kLight, kConnection, kWeighted };
  Importance importance = Importance::kLight;
  // Visibility of x from y in the importance (one shadow ray per cache point and light vertex):
  // an occluded entry is scaled by `floor` (0: exact, only the uniform share keeps its support).
  bool cache_visibility = true;
  double visibility_floor = 0.02;
  // MIS counts of the connection strategies: K each (mis=balance), or the resampled
  // draws' effective samples of the path's light vertex (mis=resampling, resampling_counts.h).
  bool resampling_mis = false;
};

// The mistake pcbpt's code makes only for its negative control, whose file
// (ctl_scene_visible_only.cpp) asks for it with the honest configuration it starts from and says
// why it is biased; no parameter of pcbpt reaches it.
enum class PcbptFlaw {
  kNone,
  // A cache point that sees no light vertex (its importances sum to 0) draws nothing, where pcbpt
  // counts it as uniform.
  kUnseenCachePointsDrawNothing,
};

// The configuration of `params` (pcbpt's scene parameters, over its defaults), such as a named
// design's; throws InputError as a run would.
PcbptConfig pcbpt_config(const ParamText& params);

std::shared_ptr<const SceneEstimator> make_pcbpt(const PcbptConfig& config,
                                                 PcbptFlaw flaw = PcbptFlaw::kNone);

}  // namespace pcbench::scene
