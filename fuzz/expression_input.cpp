// Expression text to an integrand evaluated at a few points (fuzz/fuzz_inputs.h).
#include <array>
#include <string>

#include "base/errors.h"
#include "fuzz/fuzz_inputs.h"
#include "integrands/expression.h"
#include "integrands/registry.h"

namespace pcbench::fuzz {
namespace {

// (x0, x1, y0, y1): the corners and centre of the unit cube, where expressions tend to divide by
// zero or take logarithms of 0, and points no simplification can special-case.
constexpr std::array<std::array<double, 4>, 8> kPoints = {{{0, 0, 0, 0},
                                                           {1, 1, 1, 1},
                                                           {0.5, 0.5, 0.5, 0.5},
                                                           {0, 1, 0, 1},
                                                           {1, 0, 1, 0},
                                                           {1e-300, 1, 1e-300, 1},
                                                           {0.1234, 0.8765, 0.3141, 0.2718},
                                                           {0.999999, 1e-9, 0.75, 0.25}}};

}  // namespace

Outcome check_expression_text(std::string_view text) {
  try {
    const IntegrandEntry& entry = find_integrand("expr");
    const ParamText supplied = {
        {"f", std::string(text)}, {"light_dims", "2"}, {"camera_dims", "2"}};
    const ResolvedParams params = resolve_params(entry.params, supplied, "integrand 'expr'");
    // The constructor parses and test-evaluates f; what the registry's factory makes from it.
    const ExpressionModel made(params);
    ExpressionModel copy(made);
    for (const auto& point : kPoints) {
      // Any value is an outcome (the runner counts non-finite ones); only a crash is not.
      static_cast<void>(copy.f(point.data(), point.data() + 2));
    }
    static_cast<void>(copy.reference());
    static_cast<void>(entry.make(params));
  } catch (const InputError&) {
    return Outcome::kRejected;
  }
  return Outcome::kAccepted;
}

}  // namespace pcbench::fuzz
