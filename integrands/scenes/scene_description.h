// A scene as described (by a JSON file or a built-in builder), before anything is traced: a
// triangle soup with one material and one emission per triangle, point lights, a pinhole camera,
// the image size and the maximum path length L (docs/reference/INTERFACE.md: segments from the
// camera to the emitter; L = 1 is an emitter seen directly).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "integrands/scenes/scene_math.h"

namespace pcbench::scene {

enum class MaterialKind { kDiffuse, kPhong, kMirror };

// Lambertian: f = albedo / π. Normalised Phong (Lafortune and Willems 1994): f = albedo ·
// (exponent + 2) / (2π) · cos^exponent(angle between wi and the mirror direction of wo), the
// energy-conserving lobe for albedo <= 1. Mirror: a perfect specular reflection scaled by albedo.
struct Material {
  std::string name = {};
  MaterialKind kind = MaterialKind::kDiffuse;
  Rgb albedo = {};
  double exponent = 0.0;  // Phong only
};

// One triangle: vertices in counter-clockwise order seen from the side its normal points to.
// Surfaces are one-sided for emission (an emitter radiates into its normal's hemisphere) and
// two-sided for scattering.
struct Triangle {
  Vec3 p0 = {}, p1 = {}, p2 = {};
  std::uint32_t material = 0;  // index into SceneDescription::materials
  Rgb emission = {};           // radiance leaving the front side
};

struct PointLight {
  Vec3 position = {};
  Rgb intensity = {};  // radiant intensity, the same in every direction
};

struct Camera {
  Vec3 position = {};
  Vec3 look_at = {0.0, 0.0, -1.0};
  Vec3 up = {0.0, 1.0, 0.0};
  double fov_degrees = 45.0;  // vertical field of view
};

struct SceneDescription {
  std::string name = {};
  std::string source = {};  // the file it came from, or "built-in"
  std::vector<Material> materials = {};
  std::vector<Triangle> triangles = {};
  std::vector<PointLight> point_lights = {};
  Camera camera = {};
  std::uint32_t width = 32;
  std::uint32_t height = 32;
  std::uint32_t max_length = 5;
};

}  // namespace pcbench::scene
