// `pcbench export SCENE --to cycles`: what it writes (the settings of
// integrands/scenes/cycles_export.h, the scene's data, the README's commands), what it refuses
// and its bad input. Rendering with Blender itself is the ci test export.cycles
// (tests/export_cycles_check.py); these need no Blender.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "integrands/scenes/built_in_scenes.h"
#include "test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

bool holds(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class CliExport : public ::testing::Test {
 protected:
  fs::path at(const std::string& name) const { return folder_.path() / name; }
  CliResult export_scene(const std::string& scene, const std::string& out,
                         std::vector<std::string> more = {}) {
    std::vector<std::string> args = {"export", scene, "--to", "cycles", "--out", at(out).string()};
    args.insert(args.end(), more.begin(), more.end());
    return cli(args);
  }

 private:
  TemporaryFolder folder_;
};

TEST_F(CliExport, CornellWithEverySetting) {
  const CliResult r = export_scene("cornell", "cornell", {"-p", "resolution=24x16"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(files_under(at("cornell")),
            (std::vector<std::string>{"README.md", "render.py", "scene.py"}));
  const std::string scene = read_text(at("cornell") / "scene.py");
  // The image, the path length in both renderers' counting, the camera's convention.
  for (const char* part :
       {"WIDTH, HEIGHT = 24, 16", "MAX_LENGTH = 5", "CYCLES_BOUNCES = max(MAX_LENGTH - 2, 0)",
        "cycles.max_bounces = bounces", "cycles.diffuse_bounces = bounces",
        "cycles.glossy_bounces = bounces", "data.sensor_fit = \"VERTICAL\"",
        "\"fov_degrees\": 55"}) {
    EXPECT_TRUE(holds(scene, part)) << part;
  }
  // Every setting that would bias Cycles or render another image.
  for (const char* part :
       {"cycles.use_adaptive_sampling = False", "cycles.light_sampling_threshold = 0.0",
        "cycles.sample_clamp_direct = 0.0", "cycles.sample_clamp_indirect = 0.0",
        "cycles.blur_glossy = 0.0", "cycles.caustics_reflective = True",
        "cycles.use_denoising = False", "cycles.use_guiding = False",
        "cycles.pixel_filter_type = \"BOX\"", "cycles.filter_width = 1.0",
        "background.inputs[\"Strength\"].default_value = 0.0", "image.file_format = \"OPEN_EXR\"",
        "image.color_depth = \"32\"", "surface.inputs[\"Roughness\"].default_value = 0.0"}) {
    EXPECT_TRUE(holds(scene, part)) << part;
  }
  // Emission: radiance, front side only.
  EXPECT_TRUE(
      holds(scene, "links.new(geometry.outputs[\"Backfacing\"], front_only.inputs[\"Fac\"])"));
  // Every triangle, three vertices each, in pcbench's vertex order (the emitting side).
  const scene::SceneDescription cornell = *scene::built_in_scene("cornell");
  // The data block, before the functions: one line of three vertices per triangle.
  const std::string data = scene.substr(0, scene.find("\nimport math"));
  std::size_t vertex_lines = 0;
  for (std::size_t at_line = 0; (at_line = data.find("\n        (", at_line)) != std::string::npos;
       ++at_line) {
    ++vertex_lines;
  }
  EXPECT_EQ(vertex_lines, cornell.triangles.size());
  const scene::Triangle& first = cornell.triangles.front();
  EXPECT_TRUE(holds(scene, fmt::format("({}, {}, {}), ({}, {}, {})", first.p0.x, first.p0.y,
                                       first.p0.z, first.p1.x, first.p1.y, first.p1.z)));
  const std::string render = read_text(at("cornell") / "render.py");
  EXPECT_TRUE(holds(render, "scene.cycles.seed = args.first_seed + k"));
  const std::string readme = read_text(at("cornell") / "README.md");
  const std::string dir = at("cornell").string();
  EXPECT_TRUE(holds(readme, fmt::format("blender -b -P {}/render.py -- --replicates 8 --spp 64 "
                                        "--out {}/cycles",
                                        dir, dir)))
      << readme;
  EXPECT_TRUE(holds(readme, "pcbench run -e pt -i cornell -p resolution=24x16 -p max_length=5"));
  EXPECT_TRUE(holds(readme, fmt::format("pcbench verify --images '{}/cycles/*.exr' --against '{}/"
                                        "pcbench/images/*_rep*.exr' --out {}/verify",
                                        dir, dir, dir)))
      << readme;
  EXPECT_FALSE(holds(readme, "--expect biased"));
}

TEST_F(CliExport, TheFurnaceIsVerifiedAgainstItsExactImage) {
  ASSERT_EQ(export_scene("furnace", "furnace", {"-p", "max_length=3"}).status, 0);
  const std::string readme = read_text(at("furnace") / "README.md");
  const scene::Rgb exact = scene::furnace_radiance(3);
  EXPECT_TRUE(holds(readme, fmt::format("--constant {},{},{} --out", exact.r, exact.g, exact.b)))
      << readme;
  EXPECT_FALSE(holds(readme, "pcbench run"));
  EXPECT_TRUE(holds(read_text(at("furnace") / "scene.py"), "MAX_LENGTH = 3"));
}

TEST_F(CliExport, WhatCyclesCannotRenderIsRefusedUnlessApproximate) {
  const CliResult glossy = export_scene("cornell-glossy", "glossy");
  EXPECT_EQ(glossy.status, 2);
  EXPECT_TRUE(holds(glossy.err, "material 'shiny' (phong, exponent 40)")) << glossy.err;
  EXPECT_TRUE(holds(glossy.err, "--to cycles")) << glossy.err;
  EXPECT_TRUE(holds(glossy.err, "no normalised Phong lobe")) << glossy.err;
  EXPECT_FALSE(fs::exists(at("glossy")));

  const CliResult direct = export_scene("cornell", "direct", {"-p", "max_length=1"});
  EXPECT_EQ(direct.status, 2);
  EXPECT_TRUE(holds(direct.err, "max_length 1")) << direct.err;

  std::ofstream(at("lamp.json")) << R"({
    "camera": {"position": [0, 1, 3], "look_at": [0, 1, 0]},
    "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [{"type": "quad", "corners": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]],
                "material": "white"}],
    "point_lights": [{"position": [0, 1.5, 0], "intensity": [1, 1, 1]}]
  })";
  const CliResult lamp = export_scene(at("lamp.json").string(), "lamp");
  EXPECT_EQ(lamp.status, 2);
  EXPECT_TRUE(holds(lamp.err, "point light 0 at (0, 1.5, 0)")) << lamp.err;
  EXPECT_FALSE(fs::exists(at("lamp")));

  const CliResult approximate = export_scene("cornell-glossy", "glossy", {"--approximate"});
  ASSERT_EQ(approximate.status, 0) << approximate.err;
  EXPECT_TRUE(holds(approximate.err, "warning: approximated for cycles: material 'shiny'"));
  const std::string readme = read_text(at("glossy") / "README.md");
  EXPECT_TRUE(holds(readme, "--expect biased --out")) << readme;
  EXPECT_TRUE(holds(readme, "no normalised Phong lobe")) << readme;
}

TEST_F(CliExport, BadInputExitsTwoAndWritesNothing) {
  fs::create_directories(at("full"));
  std::ofstream(at("full") / "render.py") << "# an earlier export\n";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"export", "cornell", "--to", "mitsuba", "--out", at("out").string()},
       "valid targets: cycles"},
      {{"export", "cornel", "--to", "cycles", "--out", at("out").string()},
       "did you mean 'cornell'"},
      {{"export", "genz-gaussian", "--to", "cycles", "--out", at("out").string()},
       "valid scenes: cornell"},
      {{"export", "cornell", "--to", "cycles", "--out", at("full").string()}, "is not empty"},
      {{"export", "cornell", "--to", "cycles", "-p", "resolution=0", "--out", at("out").string()},
       "resolution '0'"},
      {{"export", "cornell", "--to", "cycles", "-p", "resolution=9000", "--out",
        at("out").string()},
       "resolution '9000'"},
      {{"export", "cornell", "--to", "cycles", "-p", "max_length=65", "--out", at("out").string()},
       "max_length"},
      {{"export", "cornell", "--to", "cycles", "-p", "spp=4", "--out", at("out").string()},
       "resolution, max_length"},
      {{"export", "cornell", "--out", at("out").string()}, "--to is required"},
  };
  for (const auto& [args, message] : cases) {
    const CliResult r = cli(args);
    EXPECT_EQ(r.status, 2) << message;
    EXPECT_TRUE(holds(r.err, message)) << message << ": " << r.err;
    EXPECT_FALSE(fs::exists(at("out"))) << message;
  }
  EXPECT_EQ(files_under(at("full")), std::vector<std::string>{"render.py"});
  EXPECT_EQ(read_text(at("full") / "render.py"), "# an earlier export\n");
}

}  // namespace
}  // namespace pcbench
