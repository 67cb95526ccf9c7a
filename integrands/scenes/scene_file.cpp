#include "integrands/scenes/scene_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "base/errors.h"
#include "base/json_input.h"
#include "base/nearest_name.h"
#include "base/text_file.h"
#include "integrands/scenes/scene_obj.h"

namespace pcbench::scene {
namespace {

using Json = JsonInput::Json;

constexpr std::uint64_t kMaxResolution = 8192;
constexpr std::uint64_t kMaxPathLength = 64;
// Relative to the squared diagonal of the scene's bounding box, so that the test does not depend
// on the scene's units; far below any triangle a scene means to have, far above rounding noise.
constexpr double kDegenerateAreaFraction = 1e-12;
// |sin| of the angle between "up" and the view direction below which no image plane is defined.
constexpr double kMinUpSine = 1e-6;

const std::vector<std::string> kTopKeys = {"name",       "description", "camera", "resolution",
                                           "max_length", "materials",   "shapes", "point_lights"};
const std::vector<std::string> kCameraKeys = {"position", "look_at", "up", "fov"};
const std::vector<std::string> kMaterialTypes = {"diffuse", "phong", "mirror"};
const std::vector<std::string> kShapeTypes = {"quad", "triangle", "box", "mesh", "obj"};
const std::vector<std::string> kBoxNormals = {"outward", "inward"};
const std::vector<std::string> kLightKeys = {"position", "intensity"};

class SceneParser {
 public:
  SceneParser(std::string file, std::filesystem::path base_dir)
      : in_(std::move(file)), base_dir_(std::move(base_dir)) {}

  SceneDescription parse(std::string_view text) {
    const Json root = in_.parse(text);
    in_.require_object(root, "");
    in_.check_keys(root, "", kTopKeys);
    SceneDescription scene;
    scene.source = in_.source();
    scene.name = root.contains("name") ? in_.string_at(root["name"], "/name")
                                       : std::filesystem::path(in_.source()).stem().string();
    if (root.contains("description")) in_.string_at(root["description"], "/description");
    scene.camera = camera(in_.required(root, "", "camera"), "/camera");
    if (root.contains("resolution")) resolution(root["resolution"], scene);
    if (root.contains("max_length")) {
      scene.max_length = static_cast<std::uint32_t>(
          in_.integer_at(root["max_length"], "/max_length", 1, kMaxPathLength));
    }
    if (root.contains("materials")) materials(root["materials"], scene);
    if (!root.contains("shapes")) in_.fail("", "the scene has no \"shapes\"");
    shapes(root["shapes"], scene);
    if (root.contains("point_lights")) point_lights(root["point_lights"], scene);
    check_degenerate(scene);
    check_emitter(scene);
    return scene;
  }

 private:
  // The triangles of shape i are scene.triangles[first, first + count).
  struct ShapeRange {
    std::size_t first = 0, count = 0;
  };

  std::array<double, 3> triple_at(const Json& value, const std::string& pointer) const {
    if (!value.is_array() || value.size() != 3) {
      in_.fail(pointer, fmt::format("must be an array of 3 finite numbers, not {}",
                                    JsonInput::excerpt(value)));
    }
    std::array<double, 3> out{};
    for (std::size_t i = 0; i < 3; ++i)
      out[i] = in_.number_at(value[i], fmt::format("{}/{}", pointer, i));
    return out;
  }

  Vec3 vec3_at(const Json& value, const std::string& pointer) const {
    const auto [x, y, z] = triple_at(value, pointer);
    return {x, y, z};
  }

  // A colour with every channel in [0, max].
  Rgb rgb_at(const Json& value, const std::string& pointer, double max) const {
    const std::array<double, 3> rgb = triple_at(value, pointer);
    for (std::size_t i = 0; i < 3; ++i) {
      const double channel = rgb[i];
      if (channel < 0.0 || channel > max) {
        in_.fail(fmt::format("{}/{}", pointer, i),
                 std::isinf(max) ? fmt::format("{} is negative", channel)
                                 : fmt::format("{} is outside [0, {}]", channel, max));
      }
    }
    return {rgb[0], rgb[1], rgb[2]};
  }

  Camera camera(const Json& value, const std::string& pointer) const {
    in_.require_object(value, pointer);
    in_.check_keys(value, pointer, kCameraKeys);
    Camera camera;
    camera.position = vec3_at(in_.required(value, pointer, "position"), pointer + "/position");
    camera.look_at = vec3_at(in_.required(value, pointer, "look_at"), pointer + "/look_at");
    if (value.contains("up")) camera.up = vec3_at(value["up"], pointer + "/up");
    if (value.contains("fov")) {
      camera.fov_degrees = in_.number_at(value["fov"], pointer + "/fov");
      if (!(camera.fov_degrees > 0.0 && camera.fov_degrees < 180.0)) {
        in_.fail(pointer + "/fov",
                 fmt::format("{} degrees is outside (0, 180)", camera.fov_degrees));
      }
    }
    const Vec3 view = camera.look_at - camera.position;
    if (!(length(view) > 0.0)) {
      in_.fail(pointer + "/look_at", "equals \"position\", so the camera has no view direction");
    }
    if (!(length(camera.up) > 0.0)) in_.fail(pointer + "/up", "must not be the zero vector");
    if (!(length(cross(normalize(view), normalize(camera.up))) > kMinUpSine)) {
      in_.fail(pointer + "/up", "is parallel to the view direction (look_at - position)");
    }
    return camera;
  }

  // N (an N x N image) or "WxH".
  void resolution(const Json& value, SceneDescription& scene) const {
    const std::string pointer = "/resolution";
    const std::string why =
        fmt::format("must be an integer or \"WxH\" with W and H in [1, {}], not {}", kMaxResolution,
                    JsonInput::excerpt(value));
    if (value.is_number()) {
      scene.width = scene.height =
          static_cast<std::uint32_t>(in_.integer_at(value, pointer, 1, kMaxResolution));
      return;
    }
    if (!value.is_string()) in_.fail(pointer, why);
    const std::string text = value.get<std::string>();
    const std::size_t x = text.find('x');
    const auto side = [&](std::string_view digits) {
      std::uint64_t n = 0;
      const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
      if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() || n < 1 ||
          n > kMaxResolution) {
        in_.fail(pointer, why);
      }
      return static_cast<std::uint32_t>(n);
    };
    if (x == std::string::npos) in_.fail(pointer, why);
    scene.width = side(std::string_view(text).substr(0, x));
    scene.height = side(std::string_view(text).substr(x + 1));
  }

  void materials(const Json& value, SceneDescription& scene) {
    in_.require_object(value, "/materials");
    for (const auto& item : value.items()) {
      const std::string pointer = JsonInput::member("/materials", item.key());
      const Json& spec = item.value();
      in_.require_object(spec, pointer);
      const std::string type = in_.choice_at(in_.required(spec, pointer, "type"), pointer + "/type",
                                             "material type", kMaterialTypes);
      Material material;
      material.name = item.key();
      material.kind = type == "diffuse" ? MaterialKind::kDiffuse
                      : type == "phong" ? MaterialKind::kPhong
                                        : MaterialKind::kMirror;
      if (material.kind == MaterialKind::kPhong) {
        in_.check_keys(spec, pointer, {"type", "albedo", "exponent"});
        material.exponent =
            in_.number_at(in_.required(spec, pointer, "exponent"), pointer + "/exponent");
        if (!(material.exponent > 0.0)) in_.fail(pointer + "/exponent", "must be > 0");
      } else {
        in_.check_keys(spec, pointer, {"type", "albedo"});
      }
      material.albedo = rgb_at(in_.required(spec, pointer, "albedo"), pointer + "/albedo", 1.0);
      material_index_[material.name] = static_cast<std::uint32_t>(scene.materials.size());
      scene.materials.push_back(material);
    }
  }

  std::uint32_t material_at(const Json& value, const std::string& pointer) const {
    const std::string name = in_.string_at(value, pointer);
    const auto found = material_index_.find(name);
    if (found != material_index_.end()) return found->second;
    std::vector<std::string> defined;
    for (const auto& [known, index] : material_index_) defined.push_back(known);
    if (defined.empty()) {
      in_.fail(pointer, fmt::format("unknown material '{}'; no materials are defined (add them "
                                    "under \"materials\")",
                                    name));
    }
    in_.fail(pointer, fmt::format("unknown material '{}'; defined materials: {}{}", name,
                                  join_names(defined), did_you_mean(name, defined)));
  }

  void shapes(const Json& value, SceneDescription& scene) {
    in_.require_array(value, "/shapes");
    if (value.empty()) in_.fail("/shapes", "the scene has no shapes");
    for (std::size_t i = 0; i < value.size(); ++i) {
      const std::string pointer = fmt::format("/shapes/{}", i);
      const Json& spec = value[i];
      in_.require_object(spec, pointer);
      const std::string type = in_.choice_at(in_.required(spec, pointer, "type"), pointer + "/type",
                                             "shape type", kShapeTypes);
      std::vector<TriangleCorners> corners;
      if (type == "quad" || type == "triangle") {
        in_.check_keys(spec, pointer, {"type", "corners", "material", "emission"});
        corners = polygon(in_.required(spec, pointer, "corners"), pointer + "/corners",
                          type == "quad" ? 4 : 3);
      } else if (type == "box") {
        in_.check_keys(spec, pointer, {"type", "min", "max", "material", "normals", "emission"});
        corners = box(spec, pointer);
      } else if (type == "mesh") {
        in_.check_keys(spec, pointer, {"type", "positions", "indices", "material", "emission"});
        corners = mesh(spec, pointer);
      } else {
        in_.check_keys(spec, pointer,
                       {"type", "file", "material", "emission", "scale", "translate"});
        corners = obj(spec, pointer);
      }
      const std::uint32_t material =
          material_at(in_.required(spec, pointer, "material"), pointer + "/material");
      const Rgb emission = spec.contains("emission")
                               ? rgb_at(spec["emission"], pointer + "/emission",
                                        std::numeric_limits<double>::infinity())
                               : Rgb{};
      ranges_.push_back({scene.triangles.size(), corners.size()});
      for (const auto& [p0, p1, p2] : corners) {
        scene.triangles.push_back({p0, p1, p2, material, emission});
      }
    }
  }

  // A triangle (3 corners) or a quad (4 corners: triangles 0 1 2 and 0 2 3).
  std::vector<TriangleCorners> polygon(const Json& value, const std::string& pointer,
                                       std::size_t count) const {
    if (!value.is_array() || value.size() != count) {
      in_.fail(pointer, fmt::format("must be an array of {} points", count));
    }
    std::vector<Vec3> p;
    for (std::size_t i = 0; i < count; ++i) {
      p.push_back(vec3_at(value[i], fmt::format("{}/{}", pointer, i)));
    }
    if (count == 3) return {{p[0], p[1], p[2]}};
    return {{p[0], p[1], p[2]}, {p[0], p[2], p[3]}};
  }

  std::vector<TriangleCorners> box(const Json& spec, const std::string& pointer) const {
    const Vec3 lo = vec3_at(in_.required(spec, pointer, "min"), pointer + "/min");
    const Vec3 hi = vec3_at(in_.required(spec, pointer, "max"), pointer + "/max");
    if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) {
      in_.fail(pointer, "\"min\" must be below \"max\" in every coordinate");
    }
    const bool inward =
        spec.contains("normals") && in_.choice_at(spec["normals"], pointer + "/normals",
                                                  "normals direction", kBoxNormals) == "inward";
    // Corner c of the box: bit 0 picks x from hi, bit 1 y, bit 2 z. Each face lists its
    // corners counter-clockwise seen from outside, so cross(p1 - p0, p2 - p0) points out.
    const auto corner = [&](int c) {
      return Vec3{c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z};
    };
    constexpr int kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    std::vector<TriangleCorners> out;
    for (const auto& face : kFaces) {
      for (const auto& [a, b, c] :
           {std::array{face[0], face[1], face[2]}, std::array{face[0], face[2], face[3]}}) {
        // Swapping two corners turns the normal around.
        out.push_back(inward ? TriangleCorners{corner(a), corner(c), corner(b)}
                             : TriangleCorners{corner(a), corner(b), corner(c)});
      }
    }
    return out;
  }

  std::vector<TriangleCorners> mesh(const Json& spec, const std::string& pointer) const {
    const Json& positions = in_.required(spec, pointer, "positions");
    const Json& indices = in_.required(spec, pointer, "indices");
    if (!positions.is_array()) in_.fail(pointer + "/positions", "must be an array of points");
    if (!indices.is_array() || indices.empty()) {
      in_.fail(pointer + "/indices", "must be a non-empty array of [i, j, k] triangles");
    }
    std::vector<Vec3> p;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      p.push_back(vec3_at(positions[i], fmt::format("{}/positions/{}", pointer, i)));
    }
    std::vector<TriangleCorners> out;
    for (std::size_t t = 0; t < indices.size(); ++t) {
      const std::string where = fmt::format("{}/indices/{}", pointer, t);
      if (!indices[t].is_array() || indices[t].size() != 3) {
        in_.fail(where, "must be an array of 3 vertex indices");
      }
      TriangleCorners triangle;
      for (std::size_t k = 0; k < 3; ++k) {
        const Json& index = indices[t][k];
        if (!index.is_number_unsigned() || index.get<std::uint64_t>() >= p.size()) {
          in_.fail(
              fmt::format("{}/{}", where, k),
              fmt::format("index {} is out of range: \"positions\" has {} points (0 to {})",
                          JsonInput::excerpt(index), p.size(), p.size() == 0 ? 0 : p.size() - 1));
        }
        triangle[k] = p[index.get<std::uint64_t>()];
      }
      out.push_back(triangle);
    }
    return out;
  }

  std::vector<TriangleCorners> obj(const Json& spec, const std::string& pointer) const {
    const std::string file = in_.string_at(in_.required(spec, pointer, "file"), pointer + "/file");
    double scale = 1.0;
    if (spec.contains("scale")) {
      scale = in_.number_at(spec["scale"], pointer + "/scale");
      // A negative scale would mirror the mesh and turn its emitting side inside out.
      if (!(scale > 0.0)) in_.fail(pointer + "/scale", "must be > 0");
    }
    const Vec3 translate =
        spec.contains("translate") ? vec3_at(spec["translate"], pointer + "/translate") : Vec3{};
    // operator/ keeps an absolute `file` as it is.
    std::vector<TriangleCorners> out =
        load_obj_triangles(base_dir_ / file, fmt::format("{}: {}/file", in_.source(), pointer));
    for (TriangleCorners& triangle : out) {
      for (Vec3& p : triangle) {
        p = scale * p + translate;
        if (!is_finite(p))
          in_.fail(pointer + "/file",
                   fmt::format("OBJ file '{}' has a vertex that is not finite", file));
      }
    }
    return out;
  }

  void point_lights(const Json& value, SceneDescription& scene) const {
    in_.require_array(value, "/point_lights");
    for (std::size_t i = 0; i < value.size(); ++i) {
      const std::string pointer = fmt::format("/point_lights/{}", i);
      in_.require_object(value[i], pointer);
      in_.check_keys(value[i], pointer, kLightKeys);
      PointLight light;
      light.position = vec3_at(in_.required(value[i], pointer, "position"), pointer + "/position");
      light.intensity = rgb_at(in_.required(value[i], pointer, "intensity"), pointer + "/intensity",
                               std::numeric_limits<double>::infinity());
      scene.point_lights.push_back(light);
    }
  }

  void check_degenerate(const SceneDescription& scene) const {
    Vec3 lo = scene.triangles.front().p0, hi = lo;
    for (const Triangle& t : scene.triangles) {
      for (const Vec3& p : {t.p0, t.p1, t.p2}) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
    }
    const double min_area = kDegenerateAreaFraction * dot(hi - lo, hi - lo);
    for (std::size_t shape = 0; shape < ranges_.size(); ++shape) {
      for (std::size_t k = 0; k < ranges_[shape].count; ++k) {
        const Triangle& t = scene.triangles[ranges_[shape].first + k];
        const double area = 0.5 * length(cross(t.p1 - t.p0, t.p2 - t.p0));
        if (!(area > min_area)) {
          in_.fail(fmt::format("/shapes/{}", shape),
                   fmt::format("triangle {} is degenerate: its area {:.3g} is not above {:g} times "
                               "the squared diagonal of the scene's bounding box",
                               k, area, kDegenerateAreaFraction));
        }
      }
    }
  }

  void check_emitter(const SceneDescription& scene) const {
    for (const Triangle& t : scene.triangles) {
      if (!t.emission.is_black()) return;
    }
    for (const PointLight& light : scene.point_lights) {
      if (!light.intensity.is_black()) return;
    }
    in_.fail("",
             "the scene emits no light: give a shape a non-zero \"emission\" or add a point "
             "light with a non-zero \"intensity\"");
  }

  JsonInput in_;
  std::filesystem::path base_dir_;
  std::map<std::string, std::uint32_t> material_index_;
  std::vector<ShapeRange> ranges_;
};

}  // namespace

SceneDescription parse_scene_json(std::string_view text, const std::string& source_name,
                                  const std::filesystem::path& base_dir) {
  return SceneParser(source_name, base_dir).parse(text);
}

SceneDescription read_scene_file(const std::filesystem::path& path) {
  return parse_scene_json(read_text_file(path, "the scene file"), path.string(),
                          path.parent_path());
}

}  // namespace pcbench::scene
