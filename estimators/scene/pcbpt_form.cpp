// pcbpt's row (`pcbench list`): its parameters, read into a PcbptConfig (pcbpt.h), with the
// published design's choices and pcbench's measured defaults; its named configurations, the
// published and the legacy tile design, defined here once (the legacy design's value of each
// parameter added since keeps the runs recorded before it at their ids,
// ParamSpec::omitted_from_id_at); and what the scene tests run of it.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base/errors.h"
#include "estimators/family_params.h"
#include "estimators/scene/cache_points.h"
#include "estimators/scene/pcbpt.h"
#include "estimators/scene/scene_estimators.h"
#include "estimators/scene/scene_form.h"

namespace pcbench {
namespace scene {

const ParamText& pcbpt_published_design() {
  static const ParamText design = {
      {"nee", "draws"}, {"K", "3"}, {"M", "1024"}, {"light_tracing", "pixels"}};
  return design;
}

const ParamText& pcbpt_legacy_tile_design() {
  static const ParamText design = {{"M", "1024"},
                                   {"K", "8"},
                                   {"nee", "draws"},
                                   {"uniform_mix", "0.1"},
                                   {"cache", "tile-first-hit"},
                                   {"lookup", "tile"},
                                   {"cache_importance", "connection"},
                                   {"visibility", "ignored"},
                                   {"floor", "0"},
                                   {"light_tracing", "M"}};
  return design;
}

namespace {

// The legacy tile design's value of `key`: a run at it keeps the id it had before the parameter
// existed.
std::string legacy(const std::string& key) {
  return pcbpt_legacy_tile_design().at(key);
}

// A choice; one added after runs were recorded is left out of the run's id at `legacy` (none:
// always in the id).
ParamSpec choice_spec(std::string name, std::string value, std::vector<std::string> choices,
                      std::optional<std::string> legacy, std::string description) {
  return {.name = std::move(name),
          .type = ParamType::kChoice,
          .default_value = std::move(value),
          .description = std::move(description),
          .choices = std::move(choices),
          .omitted_from_id_at = std::move(legacy)};
}

// A number in [min, max]; `legacy` as in choice_spec (none: always in the id).
ParamSpec number_spec(std::string name, ParamType type, std::string value, double min, double max,
                      std::optional<std::string> legacy, std::string description) {
  return {.name = std::move(name),
          .type = type,
          .default_value = std::move(value),
          .description = std::move(description),
          .min = min,
          .max = max,
          .omitted_from_id_at = std::move(legacy)};
}

std::vector<ParamSpec> pcbpt_params() {
  const PcbptConfig d;
  const ParamSpec mix =
      number_spec("uniform_mix", ParamType::kReal, to_text(d.uniform_mix), 0.0, 1.0, std::nullopt,
                  "defensive share of every draw spread uniformly over the light vertices");
  ParamSpec grid = tile_spec(d.grid);
  grid.name = "grid";
  grid.description =
      "cache=every-depth: pixels per side of the block one cache path is traced "
      "through";
  grid.omitted_from_id_at = to_text(std::int64_t{d.grid});
  const ParamSpec nearest = number_spec("Nc", ParamType::kInt, std::to_string(d.nearest), 1,
                                        NearestCachePoints::kMaxFound, std::to_string(d.nearest),
                                        "lookup=nearest: cache points a camera vertex mixes");
  const ParamSpec floor =
      number_spec("floor", ParamType::kReal, to_text(d.visibility_floor), 0.0, 1.0, legacy("floor"),
                  "visibility=cache-point: factor of an occluded entry's importance (0: exact)");
  ParamSpec m = light_paths_spec(d.light_paths);
  m.description = "light paths whose vertices are the connections' candidates";
  return {m,
          vertex_draws_spec(d.draws),
          mix,
          choice_spec("cache", "every-depth", {"every-depth", "tile-first-hit"}, legacy("cache"),
                      "cache points at every camera depth of paths from a grid, or one per tile "
                      "at the first hit"),
          grid,
          tile_spec(d.tile),
          choice_spec("lookup", "nearest", {"nearest", "tile", "exact"}, legacy("lookup"),
                      "a camera vertex draws from its Nc nearest cache points (kd-tree), or "
                      "from its block's at its depth, or is its own cache point (exact: the "
                      "dense-cache limit, N_v importances and shadow rays per camera vertex)"),
          nearest,
          choice_spec("guide", d.guide_all ? "all" : "first", {"first", "all"}, std::nullopt,
                      "lookup=tile: a vertex deeper than its block's cache points draws "
                      "uniformly (first) or from the first hit's P (all)"),
          choice_spec("cache_importance", "light", {"light", "connection", "weighted"},
                      legacy("cache_importance"),
                      "a light vertex's importance at a cache point: its contribution without "
                      "the camera-side BSDF (light), the whole connection value (connection), or "
                      "that value MIS-weighted (weighted)"),
          choice_spec("visibility", d.cache_visibility ? "cache-point" : "ignored",
                      {"ignored", "cache-point"}, std::nullopt,
                      "importance times the cache point's visibility of the light vertex "
                      "(cache-point: one shadow ray per cache point and light vertex), or "
                      "unoccluded (ignored)"),
          floor,
          choice_spec("light_tracing", d.light_tracing_pixels ? "pixels" : "M", {"pixels", "M"},
                      legacy("light_tracing"),
                      "light tracing from max(M, W·H) paths as BDPT splats, or from the M "
                      "candidates"),
          choice_spec("nee", d.nee_fresh ? "fresh" : "draws", {"fresh", "draws"}, legacy("nee"),
                      "next-event estimation: every camera vertex connects to an emitter vertex "
                      "drawn for it alone, as path tracing does, and the K draws choose among the "
                      "pool's vertices with s >= 2 (fresh), or the pool's emitter vertices are "
                      "candidates of the draws (draws, the published design)"),
          choice_spec("mis", d.resampling_mis ? "resampling" : "balance", {"balance", "resampling"},
                      "balance",
                      "the balance heuristic counts K samples per connection strategy "
                      "(balance), or the draws' effective samples of the path's light vertex, "
                      "K M p̄ from the previous iteration's tables (resampling, "
                      "estimators/scene/resampling_counts.h)")};
}

PcbptConfig read_config(const ResolvedParams& p) {
  PcbptConfig c;
  c.light_paths = static_cast<std::uint32_t>(p.integer("M"));
  c.draws = static_cast<std::uint32_t>(p.integer("K"));
  c.uniform_mix = p.real("uniform_mix");
  c.every_depth = p.text("cache") == "every-depth";
  c.grid = static_cast<std::uint32_t>(p.integer("grid"));
  c.tile = static_cast<std::uint32_t>(p.integer("tile"));
  const std::string lookup = p.text("lookup");
  c.lookup = lookup == "nearest" ? PcbptConfig::Lookup::kNearest
             : lookup == "tile"  ? PcbptConfig::Lookup::kTile
                                 : PcbptConfig::Lookup::kExact;
  c.nee_fresh = p.text("nee") == "fresh";
  c.nearest = static_cast<std::uint32_t>(p.integer("Nc"));
  c.guide_all = p.text("guide") == "all";
  const std::string importance = p.text("cache_importance");
  c.importance = importance == "light"        ? PcbptConfig::Importance::kLight
                 : importance == "connection" ? PcbptConfig::Importance::kConnection
                                              : PcbptConfig::Importance::kWeighted;
  c.cache_visibility = p.text("visibility") == "cache-point";
  c.visibility_floor = p.real("floor");
  c.light_tracing_pixels = p.text("light_tracing") == "pixels";
  c.resampling_mis = p.text("mis") == "resampling";
  if (c.resampling_mis && !c.nearest_lookup()) {
    throw InputError(
        "mis=resampling needs lookup=nearest: its counts are a function of where a path's "
        "vertices are, which lookup=tile (by pixel) is not");
  }
  // A camera vertex sees light its cache points do not (occluded from them, or behind their
  // surface): only the uniform share keeps p > 0 for it.
  if (!(c.uniform_mix > 0.0) && (c.lookup != PcbptConfig::Lookup::kTile || c.cache_visibility)) {
    throw InputError(
        "uniform_mix = 0 needs lookup=tile and visibility=ignored: without mixing, light "
        "vertices the cache points cannot see are never drawn for camera vertices that can "
        "(biased; that is the negative control ctl-scene-visible-only)");
  }
  return c;
}

// pcbpt's ablations, whose MIS weights and furnace renders the scene tests check: each element
// of the default design replaced by its published or legacy value, the dense-cache limit
// (lookup=exact), and the two named designs whole. Their strategy counts differ
// (light tracing from M or W·H paths, K draws), and so do their renderings.
std::vector<NamedParams> ablations() {
  return {{"cache=tile-first-hit lookup=tile", {{"cache", "tile-first-hit"}, {"lookup", "tile"}}},
          {"lookup=tile guide=all", {{"lookup", "tile"}, {"guide", "all"}}},
          {"floor=0", {{"floor", "0"}}},
          {"visibility=ignored cache_importance=connection",
           {{"visibility", "ignored"}, {"cache_importance", "connection"}}},
          {"mis=resampling", {{"mis", "resampling"}}},
          {"mis=resampling nee=draws", {{"mis", "resampling"}, {"nee", "draws"}}},
          {"nee=draws", {{"nee", "draws"}}},
          {"lookup=exact", {{"lookup", "exact"}}},
          {"published", pcbpt_published_design()},
          {"light_tracing=pixels", {{"light_tracing", "pixels"}}},
          {"cache_importance=weighted", {{"cache_importance", "weighted"}}},
          {"legacy-tile", pcbpt_legacy_tile_design()}};
}

// The scene tests: the ablations' MIS weights; in the furnace, whose 8×8 image needs a smaller
// pool and grid than a typical run, the default design and each ablation on that pool (its M and
// K stay the small ones).
SceneTests scene_tests() {
  const ParamText small = {{"M", "256"}, {"K", "4"}, {"tile", "4"}};
  SceneTests tests{.weights = ablations(), .renders = {{"M=256 K=4 tile=4", small}}};
  for (const NamedParams& ablation : ablations()) {
    ParamText params = small;
    params.emplace("grid", "4");
    params.insert(ablation.params.begin(), ablation.params.end());  // keeps the small pool
    tests.renders.push_back({ablation.name, std::move(params)});
  }
  return tests;
}

}  // namespace

PcbptConfig pcbpt_config(const ParamText& params) {
  return read_config(resolve_params(pcbpt_params(), params, "pcbpt"));
}

}  // namespace scene

EstimatorEntry pcbpt_entry() {
  EstimatorEntry entry = family_entry(
      "pcbpt", "probabilistic connections: K draws from P ∝ importance, mixed with uniform",
      {pool_size_spec(), draws_spec(), pool_mode_spec(), draw_scheme_spec(), importance_spec(),
       uniform_mix_spec(), sampler_spec(), cache_cells_spec()},
      Selection::kImportance, DrawScheme::kIndependent,
      {.params = scene::pcbpt_params(),
       .make = [](const ResolvedParams& p) { return scene::make_pcbpt(scene::read_config(p)); }});
  entry.scene_configurations = {{"published", scene::pcbpt_published_design()},
                                {"legacy-tile", scene::pcbpt_legacy_tile_design()}};
  entry.scene_tests = scene::scene_tests();
  return entry;
}

}  // namespace pcbench
