// The table of integrands: analytic families, the expression integrand and (later) scenes.
#pragma once

#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"

namespace pcbench {

struct IntegrandEntry {
  std::string name;
  std::string description;
  bool exact = false;  // has a closed-form reference for every parameter value
  // Properties a suite or the verifier selects on: "genz", "transport", "nonuniform-density",
  // "stress", "infinite-variance", "non-negative" (f >= 0 everywhere, so ∫∫ |f| = I), ...
  std::vector<std::string> tags = {};
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<Integrand>(const ResolvedParams&)> make;

  bool has_tag(std::string_view tag) const {
    return std::find(tags.begin(), tags.end(), tag) != tags.end();
  }
  bool non_negative() const { return has_tag("non-negative"); }
};

// The analytic integrands.
const std::vector<IntegrandEntry>& integrand_registry();
// The built-in scenes (tag "scene"); scene files are found by find_integrand.
const std::vector<IntegrandEntry>& scene_registry();

// Throws InputError naming the valid integrands.
const IntegrandEntry& find_integrand(const std::string& name);

}  // namespace pcbench
