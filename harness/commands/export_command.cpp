#include "harness/commands/export_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <ostream>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "base/nearest_name.h"
#include "harness/session/session.h"
#include "integrands/registry.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/cycles_export.h"
#include "integrands/scenes/scene_integrand.h"
#include "results/context.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kTargets = {"cycles"};

// The replicates and samples the README's commands use: 8 replicates (fewer cost power fast at
// Student quantiles of few dof) of 64 samples per pixel on each side.
constexpr int kReplicates = 8;
constexpr int kSamples = 64;

// The scene as exported: its description at the command line's parameters, and the exact
// radiance of a furnace.
struct ExportedScene {
  scene::SceneDescription description;
  std::optional<scene::Rgb> exact;
};

ExportedScene exported_scene(const ExportArguments& args) {
  const std::vector<std::string>& names = scene::built_in_scene_names();
  if (!args.scene.ends_with(".json") &&
      std::find(names.begin(), names.end(), args.scene) == names.end()) {
    throw InputError(fmt::format(
        "command line: export: unknown scene '{}'{}; valid scenes: {} (or a scene file, *.json)",
        args.scene, did_you_mean(args.scene, names), join_names(names)));
  }
  const IntegrandEntry& entry = find_integrand(args.scene);
  ParamText supplied;
  std::vector<std::string> keys;
  for (const ParamSpec& spec : entry.params) keys.push_back(spec.name);
  for (const std::string& assignment : args.params) {
    const std::size_t eq = assignment.find('=');
    const std::string key = assignment.substr(0, eq);
    if (eq == std::string::npos || std::find(keys.begin(), keys.end(), key) == keys.end()) {
      throw InputError(fmt::format(
          "command line: export: -p '{}': give key=value with a key of the scene: {}{}", assignment,
          join_names(keys), eq == std::string::npos ? "" : did_you_mean(key, keys)));
    }
    supplied[key] = assignment.substr(eq + 1);
  }
  const ResolvedParams params =
      resolve_params(entry.params, supplied, "command line: export " + args.scene);
  const std::unique_ptr<Integrand> made = entry.make(params);
  const auto& integrand = dynamic_cast<const SceneIntegrand&>(*made);
  return {integrand.scene().description(), integrand.exact_radiance()};
}

// Nothing is written into a folder that holds anything: an earlier export or its renders would
// mix with this one's.
void check_out_folder(const std::string& out_dir) {
  if (out_dir.empty()) throw InputError("command line: export: --out is empty; give a folder");
  std::error_code error;
  if (!fs::exists(out_dir, error)) return;
  if (!fs::is_directory(out_dir, error)) {
    throw InputError(
        fmt::format("command line: export: --out '{}' exists and is not a folder", out_dir));
  }
  if (!fs::is_empty(out_dir, error)) {
    throw InputError(fmt::format(
        "command line: export: --out '{}' exists and is not empty; give a new or empty folder",
        out_dir));
  }
}

std::string inexact_list(const std::vector<scene::InexactPart>& parts) {
  std::vector<std::string> lines;
  for (const scene::InexactPart& p : parts) lines.push_back(p.what + ": " + p.why);
  return join_names(lines, "; ");
}

// The -p flags that reproduce the exported image in pcbench.
std::string params_flags(const scene::SceneDescription& d) {
  return fmt::format("-p resolution={}x{} -p max_length={}", d.width, d.height, d.max_length);
}

std::string readme(const ExportArguments& args, const ExportedScene& scene,
                   const std::vector<scene::InexactPart>& inexact) {
  const scene::SceneDescription& d = scene.description;
  const std::string dir = args.out_dir;
  const std::string render =
      fmt::format("blender -b -P {}/render.py -- --replicates {} --spp {} --out {}/cycles", dir,
                  kReplicates, kSamples, dir);
  const std::string expect = inexact.empty() ? "" : " --expect biased";
  std::string commands;
  if (scene.exact) {
    commands = fmt::format(
        "{}\npcbench verify --images '{}/cycles/*.exr' --constant {},{},{}{} --out {}/verify\n",
        render, dir, scene.exact->r, scene.exact->g, scene.exact->b, expect, dir);
  } else {
    commands = fmt::format(
        "{}\npcbench run -e pt -i {} {} -n {} -r {} --replicate-images -q --out {}/pcbench\n"
        "pcbench verify --images '{}/cycles/*.exr' --against '{}/pcbench/images/*_rep*.exr'{} "
        "--out {}/verify\n",
        render, args.scene, params_flags(d), kSamples, kReplicates, dir, dir, dir, expect, dir);
  }
  std::string text = fmt::format(
      "# {} for Blender's Cycles\n\n"
      "Exported by `pcbench export {} --to cycles {}{}` (pcbench {}): {}x{} pixels, paths of at "
      "most {} segments from the camera to an emitter. `scene.py` builds the scene and every "
      "setting, `render.py` renders replicates with distinct seeds into 32-bit float EXR files.\n\n"
      "## Render, then verify\n\n"
      "From the folder `pcbench export` ran in (pcbench is `build/release/pcbench` in a build "
      "tree):\n\n```sh\n{}```\n\n",
      d.name, args.scene, params_flags(d), args.approximate ? " --approximate" : "",
      pcbench_version(), d.width, d.height, d.max_length, commands);
  text += scene.exact
              ? fmt::format(
                    "The furnace's image is exact: every pixel is Le · Σ_{{k<L}} ρ^k = {:.6g}, "
                    "{:.6g}, {:.6g}, so Cycles' replicates are tested against it alone.\n\n",
                    scene.exact->r, scene.exact->g, scene.exact->b)
              : "`verify --images` tests Cycles' replicates against pcbench's own path tracer "
                "(`pt`) block by block at every scale, from 8×8 tiles to the whole image, and "
                "states the smallest bias each scale detects.\n\n";
  if (!inexact.empty()) {
    text +=
        "## Approximated (--approximate)\n\nCycles cannot render these exactly, so the "
        "comparison is expected to differ (`--expect biased`):\n\n";
    for (const scene::InexactPart& p : inexact) text += fmt::format("- {}: {}\n", p.what, p.why);
    text += "\n";
  }
  text +=
      "## What each setting is for\n\n"
      "Each of these, left at Cycles' default, biases Cycles or makes it render another image:\n\n"
      "- emission is radiance: Emission Color × Strength, front side only (a Backfacing mix)\n"
      "- camera: sensor fit Vertical with pcbench's vertical field of view, aspect W/H\n"
      "- pixel filter: Box, 1 px wide (pcbench's pixel is the mean over its square)\n"
      "- path length: max_bounces = max_length − 2 for every kind of bounce (Cycles counts "
      "bounces after the first hit and adds direct light there)\n"
      "- adaptive sampling off, light threshold 0, clamping off (direct and indirect), filter "
      "glossy 0, caustics on, denoising off, path guiding off\n"
      "- a black world; one seed per replicate (render.py: --first-seed S, replicate k gets S + "
      "k)\n"
      "- output: linear 32-bit float OpenEXR, RGB\n\n"
      "The conventions in full: pcbench's `integrands/scenes/cycles_export.h`; the guide: "
      "`docs/guide/your-renderer.md`.\n";
  return text;
}

}  // namespace

CLI::App* add_export_command(CLI::App& app, ExportArguments& args) {
  CLI::App* command = app.add_subcommand(
      "export",
      "write a scene for another renderer (Blender's Cycles), with the commands that render "
      "replicates there and verify them against pcbench");
  command->add_option("scene", args.scene, "a built-in scene or a scene file (*.json)")->required();
  command->add_option("--to", args.target, "the renderer: cycles")->required();
  command->add_option("--out,-o", args.out_dir, "a new or empty folder for the files")->required();
  command->add_option("--param,-p", args.params, "key=value, repeatable (resolution, max_length)");
  command->add_flag("--approximate", args.approximate,
                    "write what the renderer cannot represent exactly anyway; the README's "
                    "verify command then expects biased");
  return command;
}

int export_command(const ExportArguments& args, const CommandContext& context) {
  if (std::find(kTargets.begin(), kTargets.end(), args.target) == kTargets.end()) {
    throw InputError(fmt::format(
        "command line: export --to '{}': unknown target{}; valid targets: {} (Mitsuba 3 and "
        "pbrt-v4 are not Debian packages, so no test here could render with them)",
        args.target, did_you_mean(args.target, kTargets), join_names(kTargets)));
  }
  check_out_folder(args.out_dir);
  const ExportedScene scene = exported_scene(args);
  const std::vector<scene::InexactPart> inexact = scene::cycles_inexact_parts(scene.description);
  if (!inexact.empty() && !args.approximate) {
    throw InputError(fmt::format(
        "command line: export {} --to cycles: cannot be represented exactly in Cycles: {}; "
        "--approximate writes it anyway (its README then verifies with --expect biased)",
        args.scene, inexact_list(inexact)));
  }
  const fs::path dir(args.out_dir);
  try {
    fs::create_directories(dir);
    write_file_atomically(dir / "scene.py", scene::cycles_scene_script(scene.description));
    write_file_atomically(dir / "render.py", scene::cycles_render_script());
    write_file_atomically(dir / "README.md", readme(args, scene, inexact));
  } catch (const std::exception& e) {
    context.err << "pcbench: error: cannot write " << dir.string() << ": " << e.what() << "\n";
    return kExitRunFailed;
  }
  for (const scene::InexactPart& p : inexact) {
    context.err << "pcbench: warning: approximated for cycles: " << p.what << ": " << p.why << "\n";
  }
  context.out << fmt::format("{}: scene.py, render.py and README.md ({} for cycles, {}x{}, L={})\n",
                             dir.string(), scene.description.name, scene.description.width,
                             scene.description.height, scene.description.max_length);
  return kExitOk;
}

}  // namespace pcbench
