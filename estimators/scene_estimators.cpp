#include "estimators/scene_estimators.h"

#include <string>

#include "harness/errors.h"

namespace pcbench {
namespace {

using scene::Method;
using scene::RenderConfig;
using scene::SceneFlaw;

ParamSpec light_paths_spec(int default_value) {
  return {.name = "M",
          .type = ParamType::kInt,
          .default_value = std::to_string(default_value),
          .description = "light paths per iteration, shared by every pixel",
          .min = 1,
          .max = 1 << 20};
}
ParamSpec vertex_draws_spec() {
  return {.name = "K",
          .type = ParamType::kInt,
          .default_value = "8",
          .description = "light vertices drawn per camera vertex",
          .min = 1,
          .max = 1024};
}
ParamSpec mix_spec() {
  return {.name = "uniform_mix",
          .type = ParamType::kReal,
          .default_value = "0.1",
          .description = "fraction of P spread uniformly over the light vertices",
          .min = 0.0,
          .max = 1.0};
}
ParamSpec guide_spec() {
  return {.name = "guide",
          .type = ParamType::kChoice,
          .default_value = "first",
          .description =
              "camera vertices drawn from the tile's P: the first (deeper ones "
              "uniformly), or all",
          .choices = {"first", "all"}};
}
ParamSpec visibility_spec() {
  return {.name = "visibility",
          .type = ParamType::kChoice,
          .default_value = "ignored",
          .description =
              "importance at the cache point: the unoccluded connection value (ignored), or "
              "times its visibility (cache-point: one shadow ray per tile and light vertex; "
              "needs uniform_mix > 0)",
          .choices = {"ignored", "cache-point"}};
}
ParamSpec tile_spec() {
  return {.name = "tile",
          .type = ParamType::kInt,
          .default_value = "8",
          .description = "pixels per side of a screen tile sharing one importance cache point",
          .min = 1,
          .max = 8192};
}

RenderConfig read(const ResolvedParams& p, RenderConfig c) {
  if (p.has("M")) c.light_paths = static_cast<std::uint32_t>(p.integer("M"));
  if (p.has("K")) c.draws = static_cast<std::uint32_t>(p.integer("K"));
  if (p.has("uniform_mix")) c.uniform_mix = p.real("uniform_mix");
  if (p.has("tile")) c.tile = static_cast<std::uint32_t>(p.integer("tile"));
  if (p.has("guide")) c.guide_all = p.text("guide") == "all";
  if (p.has("visibility")) c.cache_visibility = p.text("visibility") == "cache-point";
  // Light the cache point cannot see may reach other pixels of its tile: only the uniform share
  // keeps P > 0 for it (without it this is the control ctl-scene-visible-only).
  if (c.cache_visibility && !(c.uniform_mix > 0.0)) {
    throw InputError(
        "visibility=cache-point needs uniform_mix > 0: without mixing, light vertices the cache "
        "point cannot see are never drawn for the pixels of its tile that can (biased; that is "
        "the negative control ctl-scene-visible-only)");
  }
  return c;
}

void give_scene_form(EstimatorEntry& e, std::vector<ParamSpec> params, RenderConfig base) {
  e.scene_params = std::move(params);
  e.make_render = [base](const ResolvedParams& p) { return read(p, base); };
}

EstimatorEntry scene_only(std::string name, std::string description, std::vector<ParamSpec> params,
                          RenderConfig base, bool biased = false) {
  EstimatorEntry e{.name = std::move(name),
                   .description = std::move(description),
                   .biased = biased,
                   .params = {},
                   .make = {}};
  give_scene_form(e, std::move(params), base);
  return e;
}

}  // namespace

void add_scene_forms(std::vector<EstimatorEntry>& table) {
  for (EstimatorEntry& e : table) {
    if (e.name == "plain") {
      give_scene_form(e, {}, {.method = Method::kBdpt});
    } else if (e.name == "vc-all") {
      give_scene_form(e, {light_paths_spec(8)},
                      {.method = Method::kVertexConnection, .light_paths = 8});
    } else if (e.name == "lvc") {
      give_scene_form(e, {light_paths_spec(1024), vertex_draws_spec()},
                      {.method = Method::kLightVertexCache, .light_paths = 1024});
    } else if (e.name == "pcbpt") {
      give_scene_form(e,
                      {light_paths_spec(1024), vertex_draws_spec(), mix_spec(), tile_spec(),
                       guide_spec(), visibility_spec()},
                      {.method = Method::kProbabilistic, .light_paths = 1024});
    }
  }
}

std::vector<EstimatorEntry> scene_only_estimators() {
  std::vector<EstimatorEntry> table;
  table.push_back(scene_only("pt", "scenes: path tracing with next-event estimation (s <= 1)", {},
                             {.method = Method::kPathTracing}));
  table.push_back(scene_only("lt", "scenes: light tracing, W·H light paths splatted (t = 1)", {},
                             {.method = Method::kLightTracing}));
  EstimatorEntry visible = scene_only(
      "ctl-scene-visible-only",
      "scenes: pcbpt with importance zero where the tile's cache point sees no light, no mixing",
      {light_paths_spec(1024), vertex_draws_spec(), tile_spec()},
      {.method = Method::kProbabilistic,
       .light_paths = 1024,
       .uniform_mix = 0.0,
       .flaw = SceneFlaw::kVisibleOnlyImportance},
      true);
  visible.declared = DeclaredWorkload{
      .integrand = "door-ajar", .samples = 16, .replicates = 16, .partners = {"plain"}};
  table.push_back(std::move(visible));
  EstimatorEntry per_vertex =
      scene_only("ctl-scene-lvc-per-vertex",
                 "scenes: the light vertex cache normalised by vertices instead of paths",
                 {light_paths_spec(1024), vertex_draws_spec()},
                 {.method = Method::kLightVertexCache,
                  .light_paths = 1024,
                  .flaw = SceneFlaw::kPerVertexNormalisation},
                 true);
  per_vertex.declared = DeclaredWorkload{
      .integrand = "cornell", .samples = 16, .replicates = 16, .partners = {"plain"}};
  table.push_back(std::move(per_vertex));
  return table;
}

}  // namespace pcbench
