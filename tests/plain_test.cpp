#include "estimators/plain.h"

#include <gtest/gtest.h>

#include "integrands/point_integrand.h"

namespace pcbench {
namespace {

// f = x0 + 10 y0 with uniform sampling: plain's estimate must be f at the sampled points, and
// the light and camera points must come from their own streams.
struct LinearModel {
  int light_dims() const { return 1; }
  int camera_dims() const { return 1; }
  Reference reference() const { return {.value = 5.5, .kind = ReferenceKind::kExact}; }
  double f(const double* x, const double* y) const { return x[0] + 10.0 * y[0]; }
};

TEST(PlainEstimator, EstimateIsFOverThePdfsOfItsOwnStreams) {
  const PointIntegrand<LinearModel> integrand{LinearModel{}};
  auto workspace = integrand.make_workspace();
  EstimatorScratch scratch;
  Counters counters;
  std::vector<ResamplingRecord> log;
  std::vector<double> estimates(5);
  const BatchContext ctx{.key = 99,
                         .replicate = 2,
                         .first_sample = 40,
                         .sample_count = 5,
                         .counters = &counters,
                         .log = &log};
  PlainEstimator().estimate_batch(ctx, *workspace, scratch, estimates);

  for (std::uint32_t i = 0; i < 5; ++i) {
    const double x =
        RandomStream(
            {.key = 99, .replicate = 2, .purpose = StreamPurpose::kLightPool, .sample = 40 + i})
            .uniform();
    const double y =
        RandomStream(
            {.key = 99, .replicate = 2, .purpose = StreamPurpose::kCameraPath, .sample = 40 + i})
            .uniform();
    EXPECT_EQ(estimates[i], x + 10.0 * y);
  }
  EXPECT_EQ(counters.connections, 5u);
  EXPECT_EQ(counters.light_paths, 5u);
  // The resampling step, as made: a pool of one, drawn once with probability 1.
  ASSERT_EQ(log.size(), 5u);
  EXPECT_EQ(log[3].sample, 43u);
  EXPECT_EQ(log[3].pmf, std::vector<double>{1.0});
  EXPECT_EQ(log[3].draws, std::vector<std::uint32_t>{0});
}

}  // namespace
}  // namespace pcbench
