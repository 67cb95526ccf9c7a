// `pcbench replay`: re-evaluates one camera sample of a run with its random streams
// (harness/run/replay.h), the command a run with a non-finite sample prints.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/commands/command_options.h"

namespace pcbench {

// The run's selection and budget, and the sample to evaluate.
struct ReplayArguments {
  std::vector<std::string> estimators;
  std::vector<std::string> integrands;
  std::vector<std::string> params;  // key=value
  std::uint64_t samples = 0;
  std::uint32_t replicates = 0;
  std::uint64_t seed = kDefaultSeed;
  std::uint32_t replicate = 0;
  std::uint64_t sample = 0;
  std::optional<std::string> run_id;
  bool json = false;
};

// Adds `replay` and its options to `app`.
CLI::App* add_replay_command(CLI::App& app, ReplayArguments& args);

// `pcbench replay`.
int replay_command(const ReplayArguments& args, const CommandContext& context);

}  // namespace pcbench
