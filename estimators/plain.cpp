#include "estimators/plain.h"

namespace pcbench {

void PlainEstimator::estimate_batch(const BatchContext& ctx, PathWorkspace& paths,
                                    EstimatorScratch& scratch, std::span<double> estimates) const {
  const std::uint32_t n = ctx.sample_count;
  paths.clear();
  paths.sample_paths(PathSide::kCamera, ctx.stream(StreamPurpose::kCameraPath), ctx.first_sample, n,
                     1);
  paths.sample_paths(PathSide::kLight, ctx.stream(StreamPurpose::kLightPool), ctx.first_sample, n,
                     1);
  scratch.pairs.resize(n);
  scratch.values.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) scratch.pairs[i] = {.light = i, .camera = i};
  paths.connect(scratch.pairs, scratch.values);

  const std::span<const double> p_x = paths.pdfs(PathSide::kLight);
  const std::span<const double> p_y = paths.pdfs(PathSide::kCamera);
  for (std::uint32_t i = 0; i < n; ++i) {
    estimates[i] = scratch.values[i] / (p_x[i] * p_y[i]);
  }
  if (ctx.log != nullptr) {
    for (std::uint32_t i = 0; i < n; ++i) {
      ctx.log->push_back({.sample = ctx.first_sample + i, .pmf = {1.0}, .draws = {0}});
    }
  }
  ctx.counters->camera_paths += n;
  ctx.counters->light_paths += n;
  ctx.counters->connections += n;
}

}  // namespace pcbench
