// `pcbench calibrate`: the verifier's self-test, of the run test on an analytic integrand
// (harness/commands/calibration.h) or of the block pyramid on scenes
// (harness/commands/tile_calibration.h). Unset options take each one's defaults.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "harness/commands/command_options.h"

namespace pcbench {

struct CalibrateArguments : ReportArguments {
  std::vector<std::string> estimators;
  std::vector<std::string> integrands;
  std::vector<std::string> params;  // key=value
  std::uint64_t samples = 0;
  std::uint32_t replicates = 0;
  std::uint32_t seeds = 0;
  bool paired = false;
};

// Adds `calibrate` and its options to `app`.
CLI::App* add_calibrate_command(CLI::App& app, CalibrateArguments& args);

// `pcbench calibrate`.
int calibrate_command(const CalibrateArguments& args, const CommandContext& context);

}  // namespace pcbench
