#include "harness/commands/command_line_grid.h"

#include <fmt/format.h>

#include "base/comma_list.h"
#include "base/errors.h"

namespace pcbench {
namespace {

// Numbers and choices never contain commas, so for them a comma separates grid values.
bool takes_comma_lists(const std::string& key, const ResolvedGrid& grid) {
  const auto typed_in = [&](const std::vector<ParamSpec>& specs) {
    for (const ParamSpec& spec : specs) {
      if (spec.name == key) return spec.type != ParamType::kText;
    }
    return false;
  };
  for (const EstimatorEntry* estimator : grid.estimators) {
    if (typed_in(estimator->params) || typed_in(estimator->scene_params)) return true;
  }
  for (const IntegrandEntry* integrand : grid.integrands) {
    if (typed_in(integrand->params)) return true;
  }
  return false;
}

}  // namespace

std::map<std::string, std::vector<std::string>> params_from_flags(
    const std::vector<std::string>& flags, const ResolvedGrid& grid) {
  std::map<std::string, std::vector<std::string>> params;
  for (const std::string& param : flags) {
    const auto equals = param.find('=');
    if (equals == std::string::npos || equals == 0) {
      throw InputError(fmt::format("command line: --param '{}': expected key=value", param));
    }
    const std::string key = param.substr(0, equals);
    const std::string value = param.substr(equals + 1);
    if (params.count(key)) {
      throw InputError(fmt::format("command line: --param '{}' is given twice", key));
    }
    std::vector<std::string>& values = params[key];
    if (!takes_comma_lists(key, grid)) {
      values.push_back(value);
      continue;
    }
    values = split_commas(value);
  }
  return params;
}

ResolvedGrid command_line_grid(const std::vector<std::string>& estimators,
                               const std::vector<std::string>& integrands,
                               const std::vector<std::string>& params) {
  ResolvedGrid grid =
      resolve_names({.estimators = estimators, .integrands = integrands, .where = "command line"});
  grid.request.params = params_from_flags(params, grid);
  return grid;
}

}  // namespace pcbench
