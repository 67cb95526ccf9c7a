#include "integrands/scenes/scene_integrand.h"

#include <fmt/format.h>

#include <atomic>
#include <charconv>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <tuple>

#include "base/errors.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/scene_file.h"

namespace pcbench {
namespace {

std::atomic<std::uint64_t> builds{0};

std::vector<ParamSpec> scene_params(const scene::SceneDescription& d) {
  return {
      {.name = "resolution",
       .type = ParamType::kText,
       .default_value = fmt::format("{}x{}", d.width, d.height),
       .description = "image size: N (N×N) or WxH, each in [1, 8192]"},
      {.name = "max_length",
       .type = ParamType::kInt,
       .default_value = std::to_string(d.max_length),
       .description = "maximum path length L in segments (L = 1: emitters seen directly)",
       .min = 1,
       .max = 64},
  };
}

std::uint32_t parse_side(std::string_view text, const std::string& whole) {
  std::uint32_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || v < 1 || v > 8192) {
    throw InputError(
        fmt::format("resolution '{}' is not N or WxH with W and H integers in [1, 8192]", whole));
  }
  return v;
}

std::pair<std::uint32_t, std::uint32_t> parse_resolution(const std::string& text) {
  const auto x = text.find('x');
  if (x == std::string::npos) {
    const std::uint32_t n = parse_side(text, text);
    return {n, n};
  }
  return {parse_side(std::string_view(text).substr(0, x), text),
          parse_side(std::string_view(text).substr(x + 1), text)};
}

// One Scene per (scene, resolution, L) for the life of the process: runs share its BVH.
std::shared_ptr<const scene::Scene> shared_scene(const scene::SceneDescription& base,
                                                 const ResolvedParams& params) {
  static std::mutex mutex;
  static std::map<std::tuple<std::string, std::string, std::uint32_t, std::uint32_t, std::uint32_t>,
                  std::shared_ptr<const scene::Scene>>
      cache;
  scene::SceneDescription d = base;
  std::tie(d.width, d.height) = parse_resolution(params.text("resolution"));
  d.max_length = static_cast<std::uint32_t>(params.integer("max_length"));
  const auto key = std::make_tuple(d.source, d.name, d.width, d.height, d.max_length);
  const std::lock_guard lock(mutex);
  auto& slot = cache[key];
  if (!slot) {
    slot = std::make_shared<const scene::Scene>(std::move(d));
    ++builds;
  }
  return slot;
}

IntegrandEntry entry_for(scene::SceneDescription description, std::string name, std::string text) {
  auto shared = std::make_shared<const scene::SceneDescription>(std::move(description));
  return {.name = std::move(name),
          .description = std::move(text),
          .exact = furnace_value(*shared).has_value(),
          .tags = {"scene", "non-negative"},
          .params = scene_params(*shared),
          .make = [shared](const ResolvedParams& params) -> std::unique_ptr<Integrand> {
            return std::make_unique<SceneIntegrand>(shared_scene(*shared, params));
          }};
}

// Whether every edge is shared by exactly two triangles (a closed surface).
bool closed_surface(const scene::SceneDescription& d) {
  using Point = std::tuple<double, double, double>;
  std::map<std::pair<Point, Point>, int> edges;
  auto key = [](const scene::Vec3& a, const scene::Vec3& b) {
    Point pa{a.x, a.y, a.z}, pb{b.x, b.y, b.z};
    return pa < pb ? std::make_pair(pa, pb) : std::make_pair(pb, pa);
  };
  for (const scene::Triangle& t : d.triangles) {
    ++edges[key(t.p0, t.p1)];
    ++edges[key(t.p1, t.p2)];
    ++edges[key(t.p2, t.p0)];
  }
  for (const auto& [edge, count] : edges) {
    if (count != 2) return false;
  }
  return true;
}

}  // namespace

std::optional<scene::Rgb> furnace_value(const scene::SceneDescription& d) {
  if (d.triangles.empty() || !d.point_lights.empty() || !scene::is_convex_enclosure(d)) return {};
  const scene::Triangle& first = d.triangles.front();
  const scene::Material& material = d.materials[first.material];
  if (material.kind != scene::MaterialKind::kDiffuse) return {};
  const double rho = material.albedo.r;
  if (material.albedo.g != rho || material.albedo.b != rho) return {};
  for (const scene::Triangle& t : d.triangles) {
    const scene::Material& m = d.materials[t.material];
    if (!(t.emission == first.emission) || m.kind != material.kind ||
        !(m.albedo == material.albedo)) {
      return {};
    }
  }
  if (!closed_surface(d)) return {};
  double series = 0.0, term = 1.0;
  for (std::uint32_t k = 0; k < d.max_length; ++k, term *= rho) series += term;
  return first.emission * series;
}

SceneIntegrand::SceneIntegrand(std::shared_ptr<const scene::Scene> scene)
    : scene_(std::move(scene)), exact_(furnace_value(scene_->description())) {}

std::unique_ptr<PathWorkspace> SceneIntegrand::make_workspace() const {
  throw std::logic_error("a scene is rendered, not sampled path by path");
}

Reference SceneIntegrand::reference() const {
  Reference r;
  if (exact_) {
    r.value = exact_->average();
    r.kind = ReferenceKind::kExact;
    r.magnitude = r.value;
  }
  return r;
}

std::vector<IntegrandEntry> scene_integrand_entries() {
  const std::map<std::string, std::string> descriptions = {
      {"cornell", "scene: diffuse Cornell box, square area light under the ceiling, two blocks"},
      {"cornell-glossy", "scene: the Cornell box with a Phong floor and tall block"},
      {"door-ajar", "scene: a room lit only through a door ajar from a lit neighbouring room"},
      {"lampshade",
       "scene: a room lit by a bulb inside a lampshade: connections to the light are occluded"},
      {"many-lights",
       "scene: 100 small lights with radiances spanning 100x; the strongest are hidden"},
      {"furnace", "scene: closed box emitting Le with albedo ρ; exact Le Σ_{k<L} ρ^k"},
  };
  std::vector<IntegrandEntry> out;
  for (const std::string& name : scene::built_in_scene_names()) {
    out.push_back(entry_for(*scene::built_in_scene(name), name, descriptions.at(name)));
  }
  return out;
}

IntegrandEntry scene_file_entry(const std::string& path) {
  scene::SceneDescription d = scene::read_scene_file(path);
  d.source = std::filesystem::absolute(path).string();
  return entry_for(std::move(d), path, "scene file " + path);
}

std::uint64_t scene_builds() {
  return builds.load();
}

}  // namespace pcbench
