#include "integrands/quadrature.h"

#include <algorithm>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <vector>

namespace pcbench {

QuadratureResult integrate_pieces(const std::function<double(double)>& g, double a, double b,
                                  std::span<const double> breakpoints, double relative_tolerance) {
  std::vector<double> cuts = {a, b};
  for (double t : breakpoints) {
    if (t > a && t < b) cuts.push_back(t);
  }
  std::sort(cuts.begin(), cuts.end());
  QuadratureResult total;
  constexpr unsigned kMaxDepth = 15;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    if (!(cuts[i + 1] > cuts[i])) continue;
    double error = 0.0;
    total.value += boost::math::quadrature::gauss_kronrod<double, 31>::integrate(
        g, cuts[i], cuts[i + 1], kMaxDepth, relative_tolerance, &error);
    total.error += error;
  }
  return total;
}

}  // namespace pcbench
