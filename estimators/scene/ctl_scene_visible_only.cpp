// ctl-scene-visible-only (scene negative control): probabilistic connections whose importance
// is zero wherever the tile's cache point sees no light, with no uniform mixing.
//
// The mistake: pcbpt (pcbpt.cpp) with visibility=cache-point and u = 0, so P = 0 for every
// light vertex the cache point cannot see, although other pixels of its tile can; a tile whose
// cache point sees none draws nothing at all. Light reaching a tile past an occluder its cache
// point sits behind is lost: biased low where visibility changes within a tile (door-ajar). In
// a convex furnace every cache point sees every light vertex and it is honest. Parameters: M, K
// and tile, with the defaults of pcbpt's legacy tile design (pcbpt_legacy_tile_design, pcbpt.h),
// and design. design=published: the same mistake in pcbpt's published design
// (pcbpt_published_design) with floor 0 and u = 0, and the M and K given (a cache point that
// sees nothing draws nothing): light its Nc nearest cache points cannot see is never drawn for
// a camera vertex that can.
// Declared workload: door-ajar, 16 spp × 16 replicates.
#include "estimators/scene/pcbpt.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {

EstimatorEntry ctl_scene_visible_only_entry() {
  // Its own defaults, whatever pcbpt's are: the legacy tile design's M, K and tile.
  const scene::PcbptConfig d = scene::pcbpt_config(scene::pcbpt_legacy_tile_design());
  EstimatorEntry e = scene_only_entry(
      "ctl-scene-visible-only",
      "scenes: pcbpt with importance zero where the tile's cache point sees no light, no mixing",
      {.params = {light_paths_spec(d.light_paths),
                  vertex_draws_spec(d.draws),
                  tile_spec(d.tile),
                  {.name = "design",
                   .type = ParamType::kChoice,
                   .default_value = "tile",
                   .description = "pcbpt's legacy tile design, or the published one (cache points "
                                  "at every depth, nearest-cache mixture) with floor 0",
                   .choices = {"tile", "published"},
                   .omitted_from_id_at = "tile"}},
       .make =
           [](const ResolvedParams& p) {
             // pcbpt's named design, with its next-event estimation through the draws and light
             // tracing from its pool (published: W·H paths; tile: M): the mistake also starves
             // next events where the cache points see no emitter.
             scene::PcbptConfig c =
                 scene::pcbpt_config(p.text("design") == "tile" ? scene::pcbpt_legacy_tile_design()
                                                                : scene::pcbpt_published_design());
             c.light_paths = static_cast<std::uint32_t>(p.integer("M"));
             c.draws = static_cast<std::uint32_t>(p.integer("K"));
             c.tile = static_cast<std::uint32_t>(p.integer("tile"));
             // The mistake: importance zero where the cache point sees no light, no mixing.
             c.visibility_floor = 0.0;
             c.uniform_mix = 0.0;
             c.cache_visibility = true;
             // And its flaw: a cache point that sees no light vertex (P all zero with u = 0) draws
             // nothing, its whole tile under design=tile, a draw that picks it under
             // design=published, although camera vertices near it may see light.
             return scene::make_pcbpt(c, scene::PcbptFlaw::kUnseenCachePointsDrawNothing);
           }},
      true);
  e.declared = DeclaredWorkload{
      .integrand = "door-ajar", .samples = 16, .replicates = 16, .partners = {"plain"}};
  return e;
}

}  // namespace pcbench
