// The table of integrands: analytic families, the expression integrand and (later) scenes.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "harness/params.h"
#include "integrands/integrand.h"

namespace pcbench {

struct IntegrandEntry {
  std::string name;
  std::string description;
  bool exact = false;  // has a closed-form reference for every parameter value
  // Properties a suite or the verifier selects on: "genz", "transport", "nonuniform-density",
  // "stress", "infinite-variance", ...
  std::vector<std::string> tags = {};
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<Integrand>(const ResolvedParams&)> make;
};

const std::vector<IntegrandEntry>& integrand_registry();

// Throws InputError naming the valid integrands.
const IntegrandEntry& find_integrand(const std::string& name);

}  // namespace pcbench
