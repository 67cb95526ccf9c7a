#include "integrands/scenes/scene_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/errors.h"
#include "tests/test_support.h"

namespace pcbench::scene {
namespace {

using Json = nlohmann::json;

// The InputError message of parsing `text` as "scene.json", or "" when it does not throw.
std::string scene_error(const std::string& text, const std::filesystem::path& base_dir = ".") {
  try {
    parse_scene_json(text, "scene.json", base_dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The smallest valid scene: a grey floor quad and an emitting triangle above it.
Json base_scene() {
  return Json::parse(R"({
    "camera": {"position": [0, 1, 3], "look_at": [0, 1, 0]},
    "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [
      {"type": "quad", "corners": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]],
       "material": "white"},
      {"type": "triangle", "corners": [[0, 2, 0], [1, 2, 0], [0, 2, 1]], "material": "white",
       "emission": [5, 5, 5]}
    ]
  })");
}

// The base scene with the value at JSON pointer `at` set to `value` (null removes it).
std::string scene_with(const std::string& at, const Json& value) {
  Json scene = base_scene();
  const Json::json_pointer pointer(at);
  if (value.is_null()) {
    scene[pointer.parent_pointer()].erase(pointer.back());
  } else {
    scene[pointer] = value;
  }
  return scene.dump(2);
}

Vec3 normal_of(const Triangle& t) {
  return cross(t.p1 - t.p0, t.p2 - t.p0);
}

TEST(SceneFileParse, EveryShapeTypeFromAFile) {
  const TemporaryFolder folder;
  std::filesystem::create_directories(folder.path() / "meshes");
  // A quad and a pentagon: tinyobjloader triangulates them into 2 + 3 triangles.
  write_text(folder.path() / "meshes" / "plate.obj",
             "mtllib missing.mtl\n"
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
             "v 0 0 1\nv 1 0 1\nv 1.5 0.5 1\nv 1 1 1\nv 0 1 1\n"
             "usemtl whatever\nf 1 2 3 4\nf 5 6 7 8 9\n");
  write_text(folder.path() / "room.json", R"({
    "description": "every shape type",
    "camera": {"position": [0, 1, 4], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov": 40},
    "resolution": "64x48",
    "max_length": 7,
    "materials": {
      "white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
      "shiny": {"type": "phong", "albedo": [0.5, 0.4, 0.3], "exponent": 40},
      "glass": {"type": "mirror", "albedo": [0.9, 0.9, 0.9]}
    },
    "shapes": [
      {"type": "quad", "corners": [[-1, 2, -1], [1, 2, -1], [1, 2, 1], [-1, 2, 1]],
       "material": "white", "emission": [4, 3, 2]},
      {"type": "triangle", "corners": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "material": "glass"},
      {"type": "box", "min": [-2, 0, -2], "max": [2, 3, 2], "material": "white",
       "normals": "inward"},
      {"type": "mesh", "positions": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
       "indices": [[0, 1, 2], [0, 2, 3]], "material": "shiny"},
      {"type": "obj", "file": "meshes/plate.obj", "material": "shiny", "scale": 2,
       "translate": [10, 0, 0]}
    ],
    "point_lights": [{"position": [0, 1.5, 0], "intensity": [1, 1, 1]}]
  })");
  const SceneDescription scene = read_scene_file(folder.path() / "room.json");
  EXPECT_EQ(scene.name, "room");
  EXPECT_EQ(scene.source, (folder.path() / "room.json").string());
  EXPECT_EQ(scene.width, 64u);
  EXPECT_EQ(scene.height, 48u);
  EXPECT_EQ(scene.max_length, 7u);
  EXPECT_EQ(scene.camera.position, (Vec3{0, 1, 4}));
  EXPECT_EQ(scene.camera.look_at, (Vec3{0, 1, 0}));
  EXPECT_EQ(scene.camera.fov_degrees, 40.0);

  // Materials in name order: glass, shiny, white.
  ASSERT_EQ(scene.materials.size(), 3u);
  EXPECT_EQ(scene.materials[0].name, "glass");
  EXPECT_EQ(scene.materials[0].kind, MaterialKind::kMirror);
  EXPECT_EQ(scene.materials[1].kind, MaterialKind::kPhong);
  EXPECT_EQ(scene.materials[1].exponent, 40.0);
  EXPECT_EQ(scene.materials[1].albedo, (Rgb{0.5, 0.4, 0.3}));
  EXPECT_EQ(scene.materials[2].kind, MaterialKind::kDiffuse);

  // quad 2 + triangle 1 + box 12 + mesh 2 + obj (quad 2 + pentagon 3).
  ASSERT_EQ(scene.triangles.size(), 2u + 1u + 12u + 2u + 5u);
  EXPECT_EQ(scene.triangles[0].emission, (Rgb{4, 3, 2}));
  EXPECT_EQ(scene.triangles[0].material, 2u);
  EXPECT_TRUE(scene.triangles[2].emission.is_black());
  EXPECT_EQ(scene.triangles[2].material, 0u);
  EXPECT_EQ(scene.triangles[15].material, 1u);         // the mesh
  EXPECT_EQ(scene.triangles[16].p2, (Vec3{0, 1, 0}));  // [0, 2, 3]
  for (std::size_t i = 17; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    EXPECT_EQ(t.material, 1u);
    for (const Vec3& p : {t.p0, t.p1, t.p2}) {  // scaled by 2, moved by 10 along x
      EXPECT_GE(p.x, 10.0);
      EXPECT_LE(p.x, 13.0);
      EXPECT_TRUE(p.z == 0.0 || p.z == 2.0);
    }
    EXPECT_GT(normal_of(t).z, 0.0);  // counter-clockwise in the file: facing +z
  }
  ASSERT_EQ(scene.point_lights.size(), 1u);
  EXPECT_EQ(scene.point_lights[0].intensity, (Rgb{1, 1, 1}));
}

TEST(SceneFileParse, QuadIsTwoTrianglesSharingCornerZero) {
  const SceneDescription scene = parse_scene_json(base_scene().dump(), "floor.json", ".");
  EXPECT_EQ(scene.name, "floor");
  EXPECT_EQ(scene.width, 32u);
  EXPECT_EQ(scene.height, 32u);
  EXPECT_EQ(scene.max_length, 5u);
  EXPECT_EQ(scene.camera.up, (Vec3{0, 1, 0}));
  ASSERT_EQ(scene.triangles.size(), 3u);
  const Vec3 c0{-1, 0, -1}, c1{-1, 0, 1}, c2{1, 0, 1}, c3{1, 0, -1};
  EXPECT_EQ(scene.triangles[0].p0, c0);
  EXPECT_EQ(scene.triangles[0].p1, c1);
  EXPECT_EQ(scene.triangles[0].p2, c2);
  EXPECT_EQ(scene.triangles[1].p0, c0);
  EXPECT_EQ(scene.triangles[1].p1, c2);
  EXPECT_EQ(scene.triangles[1].p2, c3);
  EXPECT_GT(normal_of(scene.triangles[0]).y, 0.0);  // counter-clockwise seen from above
  EXPECT_LT(normal_of(scene.triangles[2]).y, 0.0);  // the emitter faces down
}

TEST(SceneFileParse, BoxNormalsPointOutOfOrIntoTheBox) {
  for (const std::string normals : {"", "outward", "inward"}) {
    Json box = {{"type", "box"}, {"min", {-1, 0, 2}}, {"max", {3, 1, 2.5}}, {"material", "white"}};
    if (!normals.empty()) box["normals"] = normals;
    const SceneDescription scene = parse_scene_json(scene_with("/shapes/0", box), "s.json", ".");
    ASSERT_EQ(scene.triangles.size(), 12u + 1u);
    const Vec3 centre{1, 0.5, 2.25};
    double area = 0.0;
    for (std::size_t i = 0; i < 12; ++i) {
      const Triangle& t = scene.triangles[i];
      const Vec3 n = normal_of(t);
      const double side = dot(n, (t.p0 + t.p1 + t.p2) / 3.0 - centre);
      if (normals == "inward") {
        EXPECT_LT(side, 0.0) << "triangle " << i;
      } else {
        EXPECT_GT(side, 0.0) << "triangle " << i;
      }
      // Axis-aligned: exactly one non-zero component.
      EXPECT_EQ((n.x != 0.0) + (n.y != 0.0) + (n.z != 0.0), 1) << "triangle " << i;
      area += 0.5 * length(n);
    }
    EXPECT_DOUBLE_EQ(area, 2.0 * (4.0 * 1.0 + 4.0 * 0.5 + 1.0 * 0.5));
  }
}

TEST(SceneFileParse, ResolutionForms) {
  const auto size = [](const Json& resolution) {
    const SceneDescription scene =
        parse_scene_json(scene_with("/resolution", resolution), "s.json", ".");
    return std::pair(scene.width, scene.height);
  };
  EXPECT_EQ(size(16), std::pair(16u, 16u));
  EXPECT_EQ(size("64x48"), std::pair(64u, 48u));
  EXPECT_EQ(size("1x8192"), std::pair(1u, 8192u));
  EXPECT_EQ(size(8192), std::pair(8192u, 8192u));
}

TEST(SceneFileParse, PointLightAloneIsAnEmitterAndAbsoluteObjPathsWork) {
  const TemporaryFolder folder;
  write_text(folder.path() / "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  Json scene = base_scene();
  scene["shapes"][1] = {
      {"type", "obj"}, {"file", (folder.path() / "t.obj").string()}, {"material", "white"}};
  scene["point_lights"] = {{{"position", {0, 1, 0}}, {"intensity", {0, 2, 0}}}};
  const SceneDescription parsed = parse_scene_json(scene.dump(), "s.json", "/nonexistent");
  EXPECT_EQ(parsed.triangles.size(), 3u);
  EXPECT_EQ(parsed.point_lights.size(), 1u);
}

TEST(SceneFileRead, MissingFileIsAnInputError) {
  const TemporaryFolder folder;
  const std::filesystem::path missing = folder.path() / "nope.json";
  try {
    read_scene_file(missing);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_scene_file(folder.path()), InputError);  // a folder, not a file
}

struct BadScene {
  const char* label;
  std::string text;
  std::vector<std::string> expected;  // substrings of the message
};

void expect_errors(const std::vector<BadScene>& cases, const std::filesystem::path& base_dir) {
  for (const BadScene& bad : cases) {
    const std::string message = scene_error(bad.text, base_dir);
    EXPECT_FALSE(message.empty()) << bad.label << ": no InputError";
    for (const std::string& part : bad.expected) {
      EXPECT_NE(message.find(part), std::string::npos)
          << bad.label << ": '" << message << "' lacks '" << part << "'";
    }
  }
}

TEST(SceneFileErrors, BadInputsNameTheLocationAndTheReason) {
  const Json white = {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}};
  const Json tiny_mesh = {{"type", "mesh"},
                          {"positions", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
                          {"indices", {{0, 1, 3}}},
                          {"material", "white"}};
  Json negative_index = tiny_mesh;
  negative_index["indices"] = Json::parse("[[-1, 1, 2]]");
  Json black_light = Json::parse(scene_with("/shapes/1/emission", nullptr));
  black_light["point_lights"] = Json::parse(R"([{"position": [0, 1, 0], "intensity": [0, 0, 0]}])");
  const std::string black_light_only = black_light.dump();
  std::string duplicate = base_scene().dump(2);
  duplicate.replace(duplicate.find("\"emission\""), 0, "\"material\": \"white\", ");
  const std::vector<BadScene> cases = {
      {"truncated", "{\"camera\": {\"position\": [0, 1,", {"scene.json:1:", "JSON syntax error"}},
      {"malformed", "{\n  \"camera\": {},\n  oops\n}", {"scene.json:3:", "JSON syntax error"}},
      {"NaN literal",
       scene_with("/camera/fov", 1).replace(0, 1, "{\"x\": NaN,"),
       {"scene.json:1:", "JSON syntax error"}},
      {"overflow", "{\n \"max_length\": 1e999}", {"scene.json:2:16:", "1e999"}},
      {"not an object", "[1, 2]", {"scene.json: /: must be an object"}},
      {"duplicate key", duplicate, {"/shapes/1/material: key 'material' appears twice"}},
      {"unknown top key",
       scene_with("/shape", 1),
       {"/shape: unknown key 'shape'; valid keys: name, description, camera",
        "did you mean 'shapes'?"}},
      {"unknown shape key",
       scene_with("/shapes/1/emision", {1, 1, 1}),
       {"/shapes/1/emision: unknown key", "valid keys: type, corners, material, emission",
        "did you mean 'emission'?"}},
      {"unknown material key",
       scene_with("/materials/white/color", {1, 1, 1}),
       {"/materials/white/color: unknown key 'color'; valid keys: type, albedo"}},
      {"unknown camera key", scene_with("/camera/fov_degrees", 40), {"/camera/fov_degrees"}},
      {"unknown shape type",
       scene_with("/shapes/0/type", "qaud"),
       {"/shapes/0/type: unknown shape type 'qaud'; valid: quad, triangle, box, mesh, obj",
        "did you mean 'quad'?"}},
      {"unknown material type",
       scene_with("/materials/white/type", "lambert"),
       {"/materials/white/type: unknown material type 'lambert'; valid: diffuse, phong, mirror"}},
      {"unknown material name",
       scene_with("/shapes/0/material", "whte"),
       {"/shapes/0/material: unknown material 'whte'; defined materials: white",
        "did you mean 'white'?"}},
      {"no materials", scene_with("/materials", nullptr), {"no materials are defined"}},
      {"missing material",
       scene_with("/shapes/0/material", nullptr),
       {"/shapes/0: missing \"material\""}},
      {"corners not an array",
       scene_with("/shapes/0/corners", "square"),
       {"/shapes/0/corners: must be an array of 4 points"}},
      {"two-number vector",
       scene_with("/camera/position", {0, 1}),
       {"/camera/position: must be an array of 3 finite numbers"}},
      {"string coordinate",
       scene_with("/camera/position/1", "1"),
       {"/camera/position/1: must be a finite number"}},
      {"boolean coordinate",
       scene_with("/shapes/1/corners/2/0", true),
       {"/shapes/1/corners/2/0: must be a finite number"}},
      {"negative albedo",
       scene_with("/materials/white/albedo/1", -0.1),
       {"/materials/white/albedo/1: -0.1 is outside [0, 1]"}},
      {"albedo above 1",
       scene_with("/materials/white/albedo/2", 1.5),
       {"/materials/white/albedo/2: 1.5 is outside [0, 1]"}},
      {"phong without exponent",
       scene_with("/materials/shiny", {{"type", "phong"}, {"albedo", {0.5, 0.5, 0.5}}}),
       {"/materials/shiny: missing \"exponent\""}},
      {"phong exponent 0",
       scene_with("/materials/shiny",
                  {{"type", "phong"}, {"albedo", {0.5, 0.5, 0.5}}, {"exponent", 0}}),
       {"/materials/shiny/exponent: must be > 0"}},
      {"exponent on diffuse",
       scene_with("/materials/white/exponent", 4),
       {"/materials/white/exponent: unknown key"}},
      {"negative emission",
       scene_with("/shapes/1/emission/0", -1),
       {"/shapes/1/emission/0: -1 is negative"}},
      {"degenerate triangle",
       scene_with("/shapes/2", {{"type", "triangle"},
                                {"corners", {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}},
                                {"material", "white"}}),
       {"/shapes/2: triangle 0 is degenerate"}},
      {"degenerate half of a quad",
       scene_with("/shapes/0/corners/3", {1, 0, 1}),
       {"/shapes/0: triangle 1 is degenerate"}},
      {"mesh index out of range",
       scene_with("/shapes/2", tiny_mesh),
       {"/shapes/2/indices/0/2: index 3 is out of range", "has 3 points"}},
      {"mesh negative index",
       scene_with("/shapes/2", negative_index),
       {"/shapes/2/indices/0/0: index -1 is out of range"}},
      {"flat box",
       scene_with("/shapes/0",
                  {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {1, 0, 1}}, {"material", "white"}}),
       {"/shapes/0: \"min\" must be below \"max\""}},
      {"box normals",
       scene_with("/shapes/0", {{"type", "box"},
                                {"min", {0, 0, 0}},
                                {"max", {1, 1, 1}},
                                {"normals", "sideways"},
                                {"material", "white"}}),
       {"/shapes/0/normals: unknown normals direction 'sideways'; valid: outward, inward"}},
      {"look_at at position",
       scene_with("/camera/look_at", {0, 1, 3}),
       {"/camera/look_at: equals \"position\""}},
      {"up along the view",
       scene_with("/camera/up", {0, 0, -2}),
       {"/camera/up: is parallel to the view direction"}},
      {"fov 180", scene_with("/camera/fov", 180), {"/camera/fov: 180 degrees is outside (0, 180)"}},
      {"fov 0", scene_with("/camera/fov", 0), {"/camera/fov: 0 degrees is outside (0, 180)"}},
      {"missing camera", scene_with("/camera", nullptr), {"scene.json: /: missing \"camera\""}},
      {"resolution 0",
       scene_with("/resolution", 0),
       {"/resolution: must be an integer in [1, 8192]"}},
      {"resolution 2.5", scene_with("/resolution", 2.5), {"/resolution: must be an integer"}},
      {"resolution too wide",
       scene_with("/resolution", "8193x2"),
       {"/resolution: must be an integer or \"WxH\" with W and H in [1, 8192]"}},
      {"resolution 64x0", scene_with("/resolution", "64x0"), {"/resolution: must be"}},
      {"resolution 64*48", scene_with("/resolution", "64*48"), {"/resolution: must be"}},
      {"resolution x48", scene_with("/resolution", "x48"), {"/resolution: must be"}},
      {"max_length 0",
       scene_with("/max_length", 0),
       {"/max_length: must be an integer in [1, 64]"}},
      {"max_length 65",
       scene_with("/max_length", 65),
       {"/max_length: must be an integer in [1, 64]"}},
      {"max_length string", scene_with("/max_length", "5"), {"/max_length: must be an integer"}},
      {"no emitter",
       scene_with("/shapes/1/emission", nullptr),
       {"scene.json: /: the scene emits no light"}},
      {"black point light only", black_light_only, {"the scene emits no light"}},
      {"negative light intensity",
       scene_with("/point_lights", {{{"position", {0, 1, 0}}, {"intensity", {1, 1, -1}}}}),
       {"/point_lights/0/intensity/2: -1 is negative"}},
      {"light without position",
       scene_with("/point_lights", {{{"intensity", {1, 1, 1}}}}),
       {"/point_lights/0: missing \"position\""}},
      {"empty shapes", scene_with("/shapes", Json::array()), {"/shapes: the scene has no shapes"}},
      {"missing shapes",
       scene_with("/shapes", nullptr),
       {"scene.json: /: the scene has no \"shapes\""}},
  };
  EXPECT_GE(cases.size(), 15u);
  expect_errors(cases, ".");
}

TEST(SceneFileErrors, BadObjFilesNameTheFileAndTheReason) {
  const TemporaryFolder folder;
  write_text(folder.path() / "bad_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n");
  write_text(folder.path() / "no_faces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  write_text(folder.path() / "past_end.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no second\nf 1 2 3 9\n");
  const auto obj = [](const std::string& file) {
    return scene_with("/shapes/0", {{"type", "obj"}, {"file", file}, {"material", "white"}});
  };
  const std::vector<BadScene> cases = {
      {"missing OBJ",
       obj("nope.obj"),
       {"scene.json: /shapes/0/file: ", "nope.obj: cannot open the OBJ file: No such file"}},
      {"tinyobjloader error",
       obj("bad_face.obj"),
       {"/shapes/0/file: OBJ file '", "bad_face.obj' cannot be loaded", "Failed parse `f' line"}},
      {"no faces", obj("no_faces.obj"), {"no_faces.obj' has no faces"}},
      {"vertex past the end",
       obj("past_end.obj"),
       {"past_end.obj'", "face 2 refers to vertex 9 but the file has 3 vertices"}},
      {"negative scale",
       scene_with(
           "/shapes/0",
           {{"type", "obj"}, {"file", "no_faces.obj"}, {"material", "white"}, {"scale", -1}}),
       {"/shapes/0/scale: must be > 0"}},
      {"OBJ key typo",
       scene_with(
           "/shapes/0",
           {{"type", "obj"}, {"file", "x.obj"}, {"material", "white"}, {"translation", {0, 0, 0}}}),
       {"/shapes/0/translation: unknown key",
        "valid keys: type, file, material, emission, scale, translate",
        "did you mean 'translate'?"}},
  };
  expect_errors(cases, folder.path());
}

}  // namespace
}  // namespace pcbench::scene
