// `pcbench merge DIR_0 … DIR_n-1 --out DIR`: joins the --out folders of the n `--shard i/n`
// runs of one job (harness/session/shard.h) into the report one process would have written.
#pragma once

#include <string>
#include <vector>

#include "harness/commands/command_options.h"

namespace pcbench {

struct MergeArguments {
  std::vector<std::string> folders;  // the shards' --out folders
  std::string out;                   // the report's folder
};

// Adds `merge` and its options to `app`.
CLI::App* add_merge_command(CLI::App& app, MergeArguments& args);

// `pcbench merge`: checks and copies the shards' journals into --out, then finishes the
// session from them as the shards' command with --resume does.
int merge_command(const MergeArguments& args, const CommandContext& context);

}  // namespace pcbench
