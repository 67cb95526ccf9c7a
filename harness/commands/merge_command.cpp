#include "harness/commands/merge_command.h"

#include <CLI/CLI.hpp>
#include <filesystem>

#include "harness/commands/cli.h"
#include "harness/session/shard.h"

namespace pcbench {

CLI::App* add_merge_command(CLI::App& app, MergeArguments& args) {
  CLI::App* merge = app.add_subcommand(
      "merge",
      "join the --out folders of the n `--shard i/n` runs of one job into the report (and "
      "images) one process would have written");
  merge->add_option("folders", args.folders, "the shards' --out folders")->required();
  merge->add_option("--out,-o", args.out, "output folder of the report")->required();
  return merge;
}

int merge_command(const MergeArguments& args, const CommandContext& context) {
  const std::vector<std::filesystem::path> folders(args.folders.begin(), args.folders.end());
  return run_cli(merge_arguments(folders, args.out), context.out, context.err, context.interrupted);
}

}  // namespace pcbench
