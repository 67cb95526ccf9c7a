// The table of estimators: the one place an estimator is made known to pcbench (no static
// self-registration, which silently loses entries at link time).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "harness/params.h"

namespace pcbench {

struct EstimatorEntry {
  std::string name;
  std::string description;
  bool biased = false;  // a negative control: the verifier must flag it
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<Estimator>(const ResolvedParams&)> make;
};

const std::vector<EstimatorEntry>& estimator_registry();

// Throws InputError naming the valid estimators.
const EstimatorEntry& find_estimator(const std::string& name);

}  // namespace pcbench
