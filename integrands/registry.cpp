#include "integrands/registry.h"

#include <fmt/format.h>

#include "harness/errors.h"
#include "integrands/expression.h"
#include "integrands/genz.h"
#include "integrands/point_integrand.h"

namespace pcbench {
namespace {

// An entry for a PointIntegrand model class with static params() and a ResolvedParams
// constructor.
template <typename Model>
IntegrandEntry point_entry(std::string name, std::string description, bool exact,
                           std::vector<std::string> tags = {}) {
  return {.name = std::move(name),
          .description = std::move(description),
          .exact = exact,
          .tags = std::move(tags),
          .params = Model::params(),
          .make = [](const ResolvedParams& params) -> std::unique_ptr<Integrand> {
            return std::make_unique<PointIntegrand<Model>>(Model(params));
          }};
}

}  // namespace

const std::vector<IntegrandEntry>& integrand_registry() {
  static const std::vector<IntegrandEntry> table = {
      point_entry<GenzGaussian>(
          "genz-gaussian", "Genz Gaussian exp(-s² Σ (z_i - c)²) over z = (x, y)", true, {"genz"}),
      point_entry<GenzOscillatory>("genz-oscillatory",
                                   "Genz oscillatory cos(2π c + s Σ z_i) over z = (x, y)", true,
                                   {"genz"}),
      point_entry<ExpressionModel>(
          "expr", "muparser expression f(x0.., y0..) on the unit cube; reference from 'exact'",
          false),
  };
  return table;
}

const IntegrandEntry& find_integrand(const std::string& name) {
  std::vector<std::string> names;
  for (const IntegrandEntry& entry : integrand_registry()) {
    if (entry.name == name) return entry;
    names.push_back(entry.name);
  }
  throw InputError(
      fmt::format("unknown integrand '{}'; valid integrands: {}", name, join_names(names)));
}

}  // namespace pcbench
