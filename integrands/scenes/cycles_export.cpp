#include "integrands/scenes/cycles_export.h"

#include <fmt/format.h>

#include <map>
#include <utility>

namespace pcbench::scene {

namespace {

// A number that reads back as the same double in Python: the shortest that does.
std::string number(double v) {
  return fmt::format("{}", v);
}

std::string triple(double x, double y, double z) {
  return fmt::format("({}, {}, {})", number(x), number(y), number(z));
}

std::string point(const Vec3& v) {
  return triple(v.x, v.y, v.z);
}

std::string colour(const Rgb& c) {
  return triple(c.r, c.g, c.b);
}

const char* kind_name(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::kDiffuse:
      return "diffuse";
    case MaterialKind::kPhong:
      return "phong";
    case MaterialKind::kMirror:
      return "mirror";
  }
  return "diffuse";
}

// A Python string literal of a name from a scene file (any text): escaped as JSON escapes it,
// which Python reads alike for the characters a name can hold.
std::string python_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
      continue;
    }
    out += c;
  }
  return out + "\"";
}

// The triangles grouped by (material, emission), in order of first appearance: one Blender mesh
// and material each.
struct Group {
  std::uint32_t material = 0;
  Rgb emission = {};
  std::vector<const Triangle*> triangles = {};
};

std::vector<Group> groups_of(const SceneDescription& scene) {
  std::vector<Group> groups;
  std::map<std::tuple<std::uint32_t, double, double, double>, std::size_t> index;
  for (const Triangle& t : scene.triangles) {
    const auto key = std::make_tuple(t.material, t.emission.r, t.emission.g, t.emission.b);
    const auto [it, inserted] = index.emplace(key, groups.size());
    if (inserted) groups.push_back({.material = t.material, .emission = t.emission});
    groups[it->second].triangles.push_back(&t);
  }
  return groups;
}

std::string data_block(const SceneDescription& scene) {
  std::string out = fmt::format(
      "# pcbench export: scene {} ({}), {}x{} pixels, paths of at most {} segments.\n"
      "# Units and conventions: pcbench's integrands/scenes/cycles_export.h.\n\n"
      "WIDTH, HEIGHT = {}, {}\n"
      "MAX_LENGTH = {}  # pcbench's max_length: segments from the camera to the emitter\n"
      "CYCLES_BOUNCES = max(MAX_LENGTH - 2, 0)  # Cycles adds direct light after its last "
      "bounce\n",
      python_string(scene.name), python_string(scene.source), scene.width, scene.height,
      scene.max_length, scene.width, scene.height, scene.max_length);
  const Camera& c = scene.camera;
  out += fmt::format(
      "CAMERA = {{\"position\": {}, \"look_at\": {}, \"up\": {}, \"fov_degrees\": {}}}\n",
      point(c.position), point(c.look_at), point(c.up), number(c.fov_degrees));
  out += "MATERIALS = [  # kind, name, albedo, Phong exponent\n";
  for (const Material& m : scene.materials) {
    out += fmt::format("    ({}, {}, {}, {}),\n", python_string(kind_name(m.kind)),
                       python_string(m.name), colour(m.albedo), number(m.exponent));
  }
  out += "]\nGROUPS = [  # one mesh each: front-side emitted radiance, three vertices a triangle\n";
  for (const Group& g : groups_of(scene)) {
    out += fmt::format("    {{\"material\": {}, \"emission\": {}, \"vertices\": [\n", g.material,
                       colour(g.emission));
    for (const Triangle* t : g.triangles) {
      out += fmt::format("        {}, {}, {},\n", point(t->p0), point(t->p1), point(t->p2));
    }
    out += "    ]},\n";
  }
  out += "]\nPOINT_LIGHTS = [\n";
  for (const PointLight& p : scene.point_lights) {
    out += fmt::format("    {{\"position\": {}, \"intensity\": {}}},\n", point(p.position),
                       colour(p.intensity));
  }
  return out + "]\n";
}

}  // namespace

std::vector<InexactPart> cycles_inexact_parts(const SceneDescription& scene) {
  std::vector<bool> used(scene.materials.size(), false);
  for (const Triangle& t : scene.triangles) used[t.material] = true;
  std::vector<InexactPart> parts;
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    if (!used[i] || m.kind != MaterialKind::kPhong) continue;
    parts.push_back(
        {fmt::format("material '{}' (phong, exponent {})", m.name, number(m.exponent)),
         "Cycles has no normalised Phong lobe: its glossy BSDFs are microfacet models (GGX, "
         "Beckmann, Ashikhmin-Shirley), which reflect another distribution of directions"});
  }
  for (std::size_t i = 0; i < scene.point_lights.size(); ++i) {
    parts.push_back(
        {fmt::format("point light {} at {}", i, point(scene.point_lights[i].position)),
         "Cycles gives point lights in Blender watts, a convention no test here has checked "
         "against pcbench's radiant intensity"});
  }
  if (scene.max_length < 2) {
    parts.push_back({"max_length 1 (emitters seen directly)",
                     "Cycles always adds direct light at the first surface (max_bounces 0 "
                     "renders paths of 2 segments)"});
  }
  return parts;
}

std::string cycles_scene_script(const SceneDescription& scene) {
  return "\"\"\"The scene for Blender's Cycles, from pcbench export (render.py builds "
         "it).\"\"\"\n" +
         data_block(scene) + cycles_scene_functions();
}

}  // namespace pcbench::scene
