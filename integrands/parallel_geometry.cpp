#include "integrands/parallel_geometry.h"

#include <algorithm>

namespace pcbench::parallel {
namespace {

// An affine function α x + β.
struct Affine {
  double slope, offset;
  double operator()(double x) const { return slope * x + offset; }
};

// ∫_a^b H(u(x)) dx for H(u) = u / (2 √(h² + u²)) and affine u: [√(h² + u²)] / (2α) between the
// ends, written as (b - a)(u_a + u_b) / (2 (√(h² + u_a²) + √(h² + u_b²))) so that nothing cancels.
double integral_of_antiderivative(const Affine& u, double a, double b, double h) {
  const double ua = u(a), ub = u(b);
  return (b - a) * (ua + ub) / (2.0 * (std::hypot(h, ua) + std::hypot(h, ub)));
}

}  // namespace

ParamSpec distance_param() {
  return {.name = "distance",
          .type = ParamType::kReal,
          .default_value = "1",
          .description = "distance h between the light and the camera plane",
          .min = 0.01,
          .max = 100};
}

ParamSpec height_param(std::string name, std::string description) {
  return {.name = std::move(name),
          .type = ParamType::kReal,
          .default_value = "0.5",
          .description = std::move(description),
          .min = 0.01,
          .max = 0.99};
}

ParamSpec length_param(std::string name, std::string description, std::string default_value,
                       double min, double max) {
  return {.name = std::move(name),
          .type = ParamType::kReal,
          .default_value = std::move(default_value),
          .description = std::move(description),
          .min = min,
          .max = max};
}

std::vector<double> offset_kinks(double t, double lo, double hi) {
  std::vector<double> kinks;
  // -x = (lo - x)/t, 1 - x = (hi - x)/t, -x = (hi - x)/t, 1 - x = (lo - x)/t.
  for (double x : {lo / (1.0 - t), (hi - t) / (1.0 - t), hi / (1.0 - t), (lo - t) / (1.0 - t)}) {
    if (x > 0.0 && x < 1.0) kinks.push_back(x);
  }
  std::sort(kinks.begin(), kinks.end());
  return kinks;
}

double flatland_total(double h) {
  return 1.0 / (std::sqrt(1.0 + h * h) + h);
}

double flatland_through(double h, double t, double lo, double hi) {
  if (!(hi > lo)) return 0.0;
  const std::vector<double> kinks = offset_kinks(t, lo, hi);
  std::vector<double> cuts = {0.0};
  cuts.reserve(kinks.size() + 2);
  for (double x : kinks) cuts.push_back(x);
  cuts.push_back(1.0);
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a)) continue;
    // Which affine function bounds the range on this piece: decided at its midpoint.
    const double mid = 0.5 * (a + b);
    const Affine through_hi{-1.0 / t, hi / t}, through_lo{-1.0 / t, lo / t};
    const Affine segment_hi{-1.0, 1.0}, segment_lo{-1.0, 0.0};
    const Affine upper = through_hi(mid) < segment_hi(mid) ? through_hi : segment_hi;
    const Affine lower = through_lo(mid) > segment_lo(mid) ? through_lo : segment_lo;
    if (upper(mid) <= lower(mid)) continue;
    total +=
        integral_of_antiderivative(upper, a, b, h) - integral_of_antiderivative(lower, a, b, h);
  }
  return total;
}

double square_form_factor(double h) {
  // X = Y = a: F = 2/(π a²) [ ½ ln((1+a²)²/(1+2a²)) + 2a √(1+a²) atan(a/√(1+a²)) - 2a atan a ].
  // The bracket is O(a⁴) from O(a²) terms when h is large: about log10(h²) digits are lost,
  // 4 at the largest distance allowed (100).
  const double a = 1.0 / h;
  const double a2 = a * a;
  const double s = std::sqrt(1.0 + a2);
  const double bracket = 0.5 * (2.0 * std::log1p(a2) - std::log1p(2.0 * a2)) +
                         2.0 * a * s * std::atan(a / s) - 2.0 * a * std::atan(a);
  return 2.0 / (M_PI * a2) * bracket;
}

double corner_integral(double a, double b, double h) {
  const double A = a / h, B = b / h;
  const double sa = std::sqrt(1.0 + A * A), sb = std::sqrt(1.0 + B * B);
  return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2.0 * M_PI);
}

double rectangle_integral(double a0, double a1, double b0, double b1, double h) {
  if (!(a1 > a0) || !(b1 > b0)) return 0.0;
  return corner_integral(a1, b1, h) - corner_integral(a0, b1, h) - corner_integral(a1, b0, h) +
         corner_integral(a0, b0, h);
}

double FlatlandInterval::through_interval() const {
  return flatland_through(distance_, height_, lo_, hi_);
}

}  // namespace pcbench::parallel
