// `pcbench verify`: tests E[estimate] = reference. Its forms, each parsed and checked once from
// the arguments into a type of its own: a set of image files (--images,
// harness/commands/image_set_verify.h), a file of estimates (--estimates,
// harness/commands/external_verify.h), or a suite or selection planned as `run` plans it
// (harness/commands/run_command.h: a session, --exact, --shard, another MPI rank).
#pragma once

#include <string>
#include <vector>

#include "harness/commands/command_options.h"
#include "harness/commands/external_verify.h"
#include "harness/commands/image_set_verify.h"
#include "harness/commands/run_command.h"

namespace pcbench {

struct VerifyArguments {
  RunArguments run;          // a suite or selection, and what every form shares
  ExternalRequest external;  // --estimates FILE (its --against is gathered from against_files)
  ImageSetRequest images;    // --images SET (its files gathered from image_files)
  // --images and --against as given: each takes several words (the files of an unquoted glob
  // that the shell expanded), joined into one comma-separated list.
  std::vector<std::string> image_files, against_files;
  std::string crop;  // --crop X,Y,W,H
};

// Adds `verify` and its options to `app`.
CLI::App* add_verify_command(CLI::App& app, VerifyArguments& args);

// `pcbench verify`.
int verify_command(const VerifyArguments& args, const CommandContext& context);

}  // namespace pcbench
