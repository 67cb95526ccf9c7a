#include "estimators/registry.h"

#include <fmt/format.h>

#include "estimators/plain.h"
#include "harness/errors.h"

namespace pcbench {

const std::vector<EstimatorEntry>& estimator_registry() {
  static const std::vector<EstimatorEntry> table = {
      {.name = "plain",
       .description = "one fresh light path per camera sample, connected once (M = K = 1)",
       .params = {},
       .make = [](const ResolvedParams&) { return std::make_unique<PlainEstimator>(); }},
  };
  return table;
}

const EstimatorEntry& find_estimator(const std::string& name) {
  std::vector<std::string> names;
  for (const EstimatorEntry& entry : estimator_registry()) {
    if (entry.name == name) return entry;
    names.push_back(entry.name);
  }
  throw InputError(
      fmt::format("unknown estimator '{}'; valid estimators: {}", name, join_names(names)));
}

}  // namespace pcbench
