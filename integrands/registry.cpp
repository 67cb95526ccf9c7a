#include "integrands/registry.h"

#include <fmt/format.h>

#include <deque>
#include <mutex>

#include "base/errors.h"
#include "base/name_lookup.h"
#include "base/nearest_name.h"
#include "integrands/blocker.h"
#include "integrands/door.h"
#include "integrands/door_2d.h"
#include "integrands/expression.h"
#include "integrands/form_factor.h"
#include "integrands/genz.h"
#include "integrands/genz_continuous.h"
#include "integrands/genz_corner_peak.h"
#include "integrands/genz_discontinuous.h"
#include "integrands/genz_product_peak.h"
#include "integrands/linear_emitter.h"
#include "integrands/narrow_peak.h"
#include "integrands/point_integrand.h"
#include "integrands/scenes/scene_integrand.h"
#include "integrands/singular.h"
#include "integrands/sparse_support.h"
#include "integrands/wide_range.h"

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
  static const std::vector<IntegrandEntry> table = [] {
    std::vector<IntegrandEntry> analytic = {
        point_entry<GenzGaussian>("genz-gaussian",
                                  "Genz Gaussian exp(-s² Σ (z_i - c)²) over z = (x, y)", true,
                                  {"genz", "non-negative"}),
        point_entry<GenzOscillatory>("genz-oscillatory",
                                     "Genz oscillatory cos(2π c + s Σ z_i) over z = (x, y)", true,
                                     {"genz"}),
        point_entry<GenzProductPeak>("genz-product-peak",
                                     "Genz product peak Π (s^-2 + (z_i - c)²)^-1", true,
                                     {"genz", "non-negative"}),
        point_entry<GenzCornerPeak>("genz-corner-peak", "Genz corner peak (1 + s Σ z_i)^-(d+1)",
                                    true, {"genz", "non-negative"}),
        point_entry<GenzContinuous>("genz-continuous",
                                    "Genz continuous exp(-s Σ |z_i - c|); Laplace densities", true,
                                    {"genz", "nonuniform-density", "non-negative"}),
        point_entry<GenzDiscontinuous>("genz-discontinuous",
                                       "Genz discontinuous exp(s Σ z_i) if x0, y0 < c; exponential "
                                       "densities",
                                       true, {"genz", "nonuniform-density", "non-negative"}),
        point_entry<FormFactor>("form-factor", "h²/(π r⁴) between parallel unit squares", true,
                                {"transport", "non-negative"}),
        point_entry<LinearEmitter>("linear-emitter",
                                   "2 x0 h²/(π r⁴), light side sampled with p(x) = 2 x0", true,
                                   {"transport", "nonuniform-density", "non-negative"}),
        point_entry<Blocker>("blocker", "flatland kernel h²/(2 r³), zero through a strip", true,
                             {"transport", "non-negative"}),
        point_entry<Door>("door", "flatland kernel h²/(2 r³) through a narrow gap", true,
                          {"transport", "non-negative"}),
        point_entry<Door2d>("door-2d", "h²/(π r⁴) through a rectangular opening (quadrature)",
                            false, {"transport", "non-negative"}),
        point_entry<NarrowPeak>("narrow-peak", "Gaussian ridge of width w in y0 - x0", true,
                                {"stress", "non-negative"}),
        point_entry<SparseSupport>("sparse-support", "1 + x0 y0 on a square of small area", true,
                                   {"stress", "non-negative"}),
        point_entry<SingularFinite>("singular-finite", "|x0 - y0|^-α, α < 1/2", true,
                                    {"stress", "non-negative"}),
        point_entry<SingularInfinite>("singular-infinite", "|x0 - y0|^-α, α >= 1/2", true,
                                      {"stress", "infinite-variance", "non-negative"}),
        point_entry<WideRange>(
            "wide-range",
            "log-uniform light density × exponential camera density × (1 + a b): "
            "|f| over 10^-D .. 2·10^D, f/p in [1, 2]",
            true, {"stress", "nonuniform-density", "non-negative"}),
        point_entry<ExpressionModel>(
            "expr", "muparser expression f(x0.., y0..) on the unit cube; reference from 'exact'",
            false),
    };
    return analytic;
  }();
  return table;
}

const std::vector<IntegrandEntry>& scene_registry() {
  static const std::vector<IntegrandEntry> table = scene_integrand_entries();
  return table;
}

const IntegrandEntry& find_integrand(const std::string& name) {
  std::vector<std::string> names;
  const IntegrandEntry* found =
      find_by_name({&integrand_registry(), &scene_registry()}, name, names);
  if (found) return *found;
  // A scene file: read once, then kept for the life of the process (entries are referenced).
  if (name.size() > 5 && name.ends_with(".json")) {
    static std::mutex mutex;
    static std::deque<IntegrandEntry> files;
    const std::lock_guard lock(mutex);
    for (const IntegrandEntry& entry : files) {
      if (entry.name == name) return entry;
    }
    files.push_back(scene_file_entry(name));
    return files.back();
  }
  throw InputError(
      fmt::format("unknown integrand '{}'{}; valid integrands: {} (or a scene file, *.json)", name,
                  did_you_mean(name, names), join_names(names)));
}

}  // namespace pcbench
