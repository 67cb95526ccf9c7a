// `pcbench export SCENE --to cycles --out DIR [-p key=value ...] [--approximate]`: a scene for
// another renderer, to render replicates there and verify them with `verify --images`.
//
// DIR gets scene.py and render.py (integrands/scenes/cycles_export.h: the scene, every setting
// that makes Cycles unbiased and comparable, R replicates with distinct seeds) and README.md with
// the exact commands: render, pcbench's own replicates, and `verify --images` against them (or
// `--constant` for a furnace, whose image is exact). What the target cannot represent exactly is
// refused (exit 2, naming it and why) unless --approximate, when the README's verify command
// expects `biased`. Bad input (an unknown scene or target, a parameter out of range, a DIR that
// exists and is not an empty folder) is exit 2 with nothing written.
#pragma once

#include <string>
#include <vector>

#include "harness/commands/command_options.h"

namespace pcbench {

struct ExportArguments {
  std::string scene;                // a built-in scene or a scene file
  std::string target;               // cycles
  std::string out_dir;              // DIR
  std::vector<std::string> params;  // key=value: resolution, max_length
  bool approximate = false;
};

// Adds `export` and its options to `app`.
CLI::App* add_export_command(CLI::App& app, ExportArguments& args);

// `pcbench export`: exit 0 with DIR written, 2 on bad input or an inexact part (nothing written),
// 3 when a file cannot be written.
int export_command(const ExportArguments& args, const CommandContext& context);

}  // namespace pcbench
