#include "integrands/scenes/built_in_scenes.h"

#include <cmath>

namespace pcbench::scene {
namespace {

// Appends quad a-b-c-d (counter-clockwise seen from the front) as two triangles.
void add_quad(SceneDescription& s, Vec3 a, Vec3 b, Vec3 c, Vec3 d, std::uint32_t material,
              Rgb emission = {}) {
  s.triangles.push_back({a, b, c, material, emission});
  s.triangles.push_back({a, c, d, material, emission});
}

// An axis-aligned box; inward = faces seen from inside (an enclosure).
void add_box(SceneDescription& s, Vec3 lo, Vec3 hi, std::uint32_t material, bool inward,
             Rgb emission = {}) {
  const Vec3 p[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                     {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                     {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  // Faces with outward counter-clockwise winding.
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 4, 7, 3},
                           {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}};
  for (const auto& f : faces) {
    if (inward) {
      add_quad(s, p[f[3]], p[f[2]], p[f[1]], p[f[0]], material, emission);
    } else {
      add_quad(s, p[f[0]], p[f[1]], p[f[2]], p[f[3]], material, emission);
    }
  }
}

std::uint32_t add_material(SceneDescription& s, Material m) {
  s.materials.push_back(std::move(m));
  return static_cast<std::uint32_t>(s.materials.size() - 1);
}

SceneDescription cornell(bool glossy) {
  SceneDescription s;
  s.name = glossy ? "cornell-glossy" : "cornell";
  s.source = "built-in";
  const auto white = add_material(s, {"white", MaterialKind::kDiffuse, {0.73, 0.73, 0.73}, 0.0});
  const auto red = add_material(s, {"red", MaterialKind::kDiffuse, {0.65, 0.05, 0.05}, 0.0});
  const auto green = add_material(s, {"green", MaterialKind::kDiffuse, {0.12, 0.45, 0.15}, 0.0});
  const auto shiny =
      glossy ? add_material(s, {"shiny", MaterialKind::kPhong, {0.7, 0.7, 0.7}, 40.0}) : white;
  const auto light = add_material(s, {"light", MaterialKind::kDiffuse, {0.78, 0.78, 0.78}, 0.0});
  // The room [0,1] x [0,1] x [0,1.2]; the camera stands inside near the front wall z = 1.2.
  add_quad(s, {0, 0, 0}, {0, 0, 1.2}, {1, 0, 1.2}, {1, 0, 0}, glossy ? shiny : white);  // floor
  add_quad(s, {0, 1, 0}, {1, 1, 0}, {1, 1, 1.2}, {0, 1, 1.2}, white);                   // ceiling
  add_quad(s, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, white);                       // back
  add_quad(s, {0, 0, 1.2}, {0, 1, 1.2}, {1, 1, 1.2}, {1, 0, 1.2}, white);               // front
  add_quad(s, {0, 0, 0}, {0, 1, 0}, {0, 1, 1.2}, {0, 0, 1.2}, red);                     // left
  add_quad(s, {1, 0, 0}, {1, 0, 1.2}, {1, 1, 1.2}, {1, 1, 0}, green);                   // right
  // The light faces down, just under the ceiling.
  add_quad(s, {0.4, 0.99, 0.4}, {0.6, 0.99, 0.4}, {0.6, 0.99, 0.6}, {0.4, 0.99, 0.6}, light,
           {17.0, 12.0, 4.0});
  add_box(s, {0.55, 0.0, 0.45}, {0.8, 0.3, 0.7}, white, false);                   // short block
  add_box(s, {0.2, 0.0, 0.2}, {0.45, 0.6, 0.45}, glossy ? shiny : white, false);  // tall block
  s.camera = {{0.5, 0.5, 1.15}, {0.5, 0.45, 0.0}, {0.0, 1.0, 0.0}, 55.0};
  return s;
}

SceneDescription door() {
  SceneDescription s;
  s.name = "door-ajar";
  s.source = "built-in";
  const auto white = add_material(s, {"white", MaterialKind::kDiffuse, {0.75, 0.75, 0.75}, 0.0});
  const auto wood = add_material(s, {"wood", MaterialKind::kDiffuse, {0.6, 0.45, 0.3}, 0.0});
  // Two rooms: A is x in [-2, 0] (the camera's), B is x in [0, 2] (the light's), both
  // y in [0, 1.2], z in [0, 2], inside one box, split by a wall at x = 0.
  add_box(s, {-2.0, 0.0, 0.0}, {2.0, 1.2, 2.0}, white, true);
  // The wall, around a door opening z in [0.8, 1.2], y in [0, 0.9]. Two-sided quads.
  add_quad(s, {0, 0, 0}, {0, 0, 0.8}, {0, 1.2, 0.8}, {0, 1.2, 0}, white);
  add_quad(s, {0, 0, 1.2}, {0, 0, 2.0}, {0, 1.2, 2.0}, {0, 1.2, 1.2}, white);
  add_quad(s, {0, 0.9, 0.8}, {0, 0.9, 1.2}, {0, 1.2, 1.2}, {0, 1.2, 0.8}, white);
  // The door: hinged at z = 1.2, swung 8 degrees into room B, leaving a gap at z = 0.8.
  const double angle = 8.0 * kPi / 180.0;
  const Vec3 free_edge{0.4 * std::sin(angle), 0.0, 1.2 - 0.4 * std::cos(angle)};
  add_quad(s, {0, 0, 1.2}, free_edge, free_edge + Vec3{0, 0.9, 0}, {0, 0.9, 1.2}, wood);
  // The light: a panel under room B's ceiling, facing down.
  add_quad(s, {1.2, 1.19, 0.6}, {1.6, 1.19, 0.6}, {1.6, 1.19, 1.4}, {1.2, 1.19, 1.4}, white,
           {40.0, 36.0, 30.0});
  s.camera = {{-1.9, 0.7, 1.0}, {0.0, 0.4, 1.0}, {0.0, 1.0, 0.0}, 60.0};
  return s;
}

SceneDescription lampshade() {
  SceneDescription s;
  s.name = "lampshade";
  s.source = "built-in";
  const auto white = add_material(s, {"white", MaterialKind::kDiffuse, {0.75, 0.75, 0.75}, 0.0});
  const auto cloth = add_material(s, {"cloth", MaterialKind::kDiffuse, {0.8, 0.7, 0.5}, 0.0});
  const auto wood = add_material(s, {"wood", MaterialKind::kDiffuse, {0.6, 0.45, 0.3}, 0.0});
  // The room x, z in [0, 2], y in [0, 1.6].
  add_box(s, {0.0, 0.0, 0.0}, {2.0, 1.6, 2.0}, white, true);
  // The shade: a square tube open at both ends around (1.5, 0.5) in x, z, from y = 0.7 to 1.2.
  // Two-sided quads: light bounces inside it, the room sees its outside.
  const double x0 = 1.3, x1 = 1.7, z0 = 0.3, z1 = 0.7, y0 = 0.7, y1 = 1.2;
  add_quad(s, {x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0}, cloth);
  add_quad(s, {x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1}, cloth);
  add_quad(s, {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1}, cloth);
  add_quad(s, {x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0}, cloth);
  // The bulb: a small panel inside the shade facing up, on a thin stand. Only the ceiling patch
  // above the shade and the shade's inside see it, so nearly every connection from the room to
  // the emitter or to a first light bounce is blocked by the shade.
  add_quad(s, {1.42, 0.75, 0.42}, {1.42, 0.75, 0.58}, {1.58, 0.75, 0.58}, {1.58, 0.75, 0.42}, white,
           {300.0, 270.0, 220.0});
  add_box(s, {1.48, 0.0, 0.48}, {1.52, 0.74, 0.52}, wood, false);
  add_box(s, {0.5, 0.0, 0.8}, {1.0, 0.45, 1.3}, wood, false);  // a low table
  s.camera = {{0.3, 0.7, 1.9}, {1.3, 0.6, 0.4}, {0.0, 1.0, 0.0}, 60.0};
  return s;
}

// The fractional part of n·step: a fixed low-discrepancy sequence in [0, 1) (no generator).
double sequence(int n, double step) {
  const double v = n * step;
  return v - std::floor(v);
}

SceneDescription many_lights() {
  SceneDescription s;
  s.name = "many-lights";
  s.source = "built-in";
  // Grey walls and ceiling keep the indirect light low, so that the floor shows the direct
  // light's shadow edges.
  const auto floor = add_material(s, {"floor", MaterialKind::kDiffuse, {0.7, 0.7, 0.7}, 0.0});
  const auto grey = add_material(s, {"grey", MaterialKind::kDiffuse, {0.45, 0.45, 0.45}, 0.0});
  const auto wood = add_material(s, {"wood", MaterialKind::kDiffuse, {0.6, 0.45, 0.3}, 0.0});
  const auto metal = add_material(s, {"metal", MaterialKind::kDiffuse, {0.4, 0.4, 0.45}, 0.0});
  // The room x, z in [0, 2], y in [0, 1], faces seen from inside. A partition at x = 1.4 up to
  // y = 0.8 closes off an alcove x in [1.4, 2]; its lights reach the camera's side only through
  // the 0.2 gap under the ceiling: the column nearest the partition lights the floor x < ~1 (a
  // straight shadow edge along z), the next one a strip along the far wall, the last none of it.
  add_quad(s, {0, 0, 0}, {0, 0, 2}, {2, 0, 2}, {2, 0, 0}, floor);
  add_quad(s, {0, 1, 0}, {2, 1, 0}, {2, 1, 2}, {0, 1, 2}, grey);  // ceiling
  add_quad(s, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}, grey);  // back
  add_quad(s, {0, 0, 2}, {0, 1, 2}, {2, 1, 2}, {2, 0, 2}, grey);  // front
  add_quad(s, {0, 0, 0}, {0, 1, 0}, {0, 1, 2}, {0, 0, 2}, grey);  // left
  add_quad(s, {2, 0, 0}, {2, 0, 2}, {2, 1, 2}, {2, 1, 0}, grey);  // right
  const double partition_x = 1.4, partition_top = 0.8;
  add_quad(s, {partition_x, 0, 0}, {partition_x, 0, 2}, {partition_x, partition_top, 2},
           {partition_x, partition_top, 0}, grey);
  // A low table and a pillar on the floor, each with its own shadows.
  add_box(s, {0.2, 0.0, 0.7}, {0.6, 0.3, 1.0}, wood, false);
  add_box(s, {0.85, 0.0, 0.35}, {1.0, 0.7, 0.5}, grey, false);
  // 10 × 10 square emitters facing down just under the ceiling, at x, z = 0.1 + 0.2 · (i, j).
  // Radiance spans two orders of magnitude by group, each light's place within its group from a
  // fixed sequence: the open lights of the camera's side (side 0.03) 6 · [1, 10], the alcove's
  // (side 0.04) 6 · [25, 100], and six lights of the camera's side (side 0.06) sunk in deep cans
  // (open square tubes from the ceiling down to y = 0.65) 6 · [40, 100], each lighting a pool of
  // floor with a sharp rim. Selection by power picks an alcove or can light ~95% of the time,
  // and from most of the floor those are hidden.
  const int cans[6][2] = {{1, 1}, {3, 3}, {5, 1}, {5, 5}, {1, 5}, {6, 7}};
  const double height = 0.99;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      const double x = 0.1 + 0.2 * i, z = 0.1 + 0.2 * j;
      const int n = 10 * i + j;
      const double h = sequence(n, 0.6180339887498949);
      const double tint = sequence(n, 0.7548776662466927);
      bool in_can = false;
      for (const auto& c : cans) in_can = in_can || (c[0] == i && c[1] == j);
      const double exponent = x > partition_x ? 1.4 + 0.6 * h : (in_can ? 1.6 + 0.4 * h : 1.0 * h);
      const double half = in_can ? 0.03 : (x > partition_x ? 0.02 : 0.015);
      const double radiance = 6.0 * std::pow(10.0, exponent);
      const Rgb emission = Rgb{1.0, 0.8 + 0.2 * tint, 0.6 + 0.4 * tint} * radiance;
      add_quad(s, {x - half, height, z - half}, {x + half, height, z - half},
               {x + half, height, z + half}, {x - half, height, z + half}, grey, emission);
      if (in_can) {
        // Two-sided walls, open at the bottom, meeting the ceiling.
        const double x0 = x - 0.05, x1 = x + 0.05, z0 = z - 0.05, z1 = z + 0.05;
        const double y0 = 0.65, y1 = 1.0;
        add_quad(s, {x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0}, metal);
        add_quad(s, {x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1}, metal);
        add_quad(s, {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1}, metal);
        add_quad(s, {x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0}, metal);
      }
    }
  }
  s.camera = {{0.7, 0.9, 1.95}, {0.75, 0.0, 0.6}, {0.0, 1.0, 0.0}, 65.0};
  return s;
}

SceneDescription furnace() {
  SceneDescription s;
  s.name = "furnace";
  s.source = "built-in";
  const auto wall = add_material(
      s, {"wall", MaterialKind::kDiffuse, {kFurnaceAlbedo, kFurnaceAlbedo, kFurnaceAlbedo}, 0.0});
  add_box(s, {0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, wall, true, kFurnaceEmission);
  s.camera = {{0.5, 0.5, 0.9}, {0.5, 0.5, 0.0}, {0.0, 1.0, 0.0}, 60.0};
  return s;
}

}  // namespace

const std::vector<std::string>& built_in_scene_names() {
  static const std::vector<std::string> names = {"cornell",   "cornell-glossy", "door-ajar",
                                                 "lampshade", "many-lights",    "furnace"};
  return names;
}

std::optional<SceneDescription> built_in_scene(const std::string& name) {
  if (name == "cornell") return cornell(false);
  if (name == "cornell-glossy") return cornell(true);
  if (name == "door-ajar") return door();
  if (name == "lampshade") return lampshade();
  if (name == "many-lights") return many_lights();
  if (name == "furnace") return furnace();
  return std::nullopt;
}

Rgb furnace_radiance(std::uint32_t max_length) {
  double series = 0.0, term = 1.0;
  for (std::uint32_t k = 0; k < max_length; ++k) {
    series += term;
    term *= kFurnaceAlbedo;
  }
  return kFurnaceEmission * series;
}

}  // namespace pcbench::scene
