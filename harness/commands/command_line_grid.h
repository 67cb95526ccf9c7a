// The -e/-i/-p selection of run, verify, calibrate, replay and reference as a grid of runs.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "harness/plan/plan.h"

namespace pcbench {

// Splits `--param` flags (key=value) into key -> values. Only numeric and choice keys are split
// on commas (a grid), so an expression such as f=min(x0,y0) stays whole.
std::map<std::string, std::vector<std::string>> params_from_flags(
    const std::vector<std::string>& params, const ResolvedGrid& grid);

// The command line's estimators, integrands and --param flags as one grid, its names resolved.
ResolvedGrid command_line_grid(const std::vector<std::string>& estimators,
                               const std::vector<std::string>& integrands,
                               const std::vector<std::string>& params);

}  // namespace pcbench
