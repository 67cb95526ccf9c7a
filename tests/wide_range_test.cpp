// The wide-range integrand: its samplers follow the densities they return (the ranks a(x0),
// b(y0) are Uniform(0, 1): Kolmogorov–Smirnov, budget 1e-4 each, fixed seeds), f / (p(x) p(y))
// = 1 + a b lies in [1, 2], and f and the approximate importance span the ranges they claim.
#include "integrands/wide_range.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "harness/run/diagnostics.h"
#include "integrands/registry.h"

namespace pcbench {
namespace {

WideRange make_wide_range(const std::string& decades) {
  const IntegrandEntry& entry = find_integrand("wide-range");
  return WideRange(resolve_params(entry.params, {{"decades", decades}}, entry.name));
}

TEST(CatalogWideRange, SamplesItsDensitiesAndSpansItsRange) {
  for (const std::string decades : {"1", "12", "300", "307"}) {
    const WideRange model = make_wide_range(decades);
    const double d = std::stod(decades);
    constexpr int kSamples = 20000;
    std::vector<double> light_ranks, camera_ranks;
    double largest_f = 0.0, smallest_w = INFINITY, largest_w = 0.0;
    RandomStream light_rng({.key = 41, .purpose = StreamPurpose::kLightPool});
    RandomStream camera_rng({.key = 42, .purpose = StreamPurpose::kCameraPath});
    for (int i = 0; i < kSamples; ++i) {
      double x = 0.0, y = 0.0;
      const double p_x = model.sample_light(light_rng, &x);
      const double p_y = model.sample_camera(camera_rng, &y);
      ASSERT_EQ(p_x, model.light_pdf(&x)) << decades;
      ASSERT_EQ(p_y, model.camera_pdf(&y)) << decades;
      light_ranks.push_back(model.light_rank(x));
      camera_ranks.push_back(model.camera_rank(y));
      const double f = model.f(&x, &y);
      const double ratio = f / (p_x * p_y);
      ASSERT_GE(ratio, 1.0 - 1e-12) << decades;
      ASSERT_LE(ratio, 2.0 + 1e-12) << decades;
      const double w = model.approximate_importance(&x, &y);
      ASSERT_EQ(std::fpclassify(f), FP_NORMAL) << decades << ": f = " << f;
      ASSERT_EQ(std::fpclassify(w), FP_NORMAL) << decades << ": w = " << w;
      largest_f = std::max(largest_f, f);
      smallest_w = std::min(smallest_w, w);
      largest_w = std::max(largest_w, w);
    }
    EXPECT_GT(ks_uniform(light_ranks).p_value, 1e-4) << decades;
    EXPECT_GT(ks_uniform(camera_ranks).p_value, 1e-4) << decades;
    // f reaches 2 × 10^D / λ at most, w spans 10^-D .. 2 × 10^D (both log-uniform in a rank):
    // 20000 samples come within a tenth of the range of the ends.
    EXPECT_GT(std::log10(largest_f), 0.9 * d - 1) << decades;
    EXPECT_LE(largest_f, 2.0 * std::pow(10.0, d)) << decades;
    EXPECT_LT(std::log10(smallest_w), -0.9 * d) << decades;
    EXPECT_GT(std::log10(largest_w), 0.9 * d) << decades;
    EXPECT_LE(largest_w, 2.0 * std::pow(10.0, d)) << decades;
  }
}

}  // namespace
}  // namespace pcbench
