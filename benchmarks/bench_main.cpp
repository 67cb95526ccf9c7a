// Microbenchmarks (Google Benchmark). Run: build/release/pcbench_bench
#include <benchmark/benchmark.h>

#include "estimators/discrete_sampler.h"
#include "estimators/registry.h"
#include "harness/rng.h"
#include "harness/tally.h"
#include "integrands/genz.h"
#include "integrands/point_integrand.h"

namespace pcbench {
namespace {

void BM_PhiloxBlock(benchmark::State& state) {
  PhiloxCounter counter{0, 0, 0, 0};
  for (auto _ : state) {
    benchmark::DoNotOptimize(philox4x32_10(counter, {0x12345678u, 0x9ABCDEF0u}));
    ++counter[0];
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PhiloxBlock);

void BM_UniformDouble(benchmark::State& state) {
  RandomStream rng({.key = 1});
  for (auto _ : state) benchmark::DoNotOptimize(rng.uniform());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_UniformDouble);

void BM_TallyAdd(benchmark::State& state) {
  Tally tally;
  double x = 0.5;
  std::uint64_t i = 0;
  for (auto _ : state) {
    x = x * 0.999 + 0.001;
    tally.add(x, i++);
  }
  benchmark::DoNotOptimize(tally.mean());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_TallyAdd);

// The plain estimator on a cheap integrand, one batch per iteration.
void BM_PlainGenzGaussianBatch(benchmark::State& state) {
  ResolvedParams params;
  params.set("light_dims", std::int64_t{1});
  params.set("camera_dims", std::int64_t{1});
  params.set("sharpness", 4.0);
  params.set("center", 0.5);
  const PointIntegrand<GenzGaussian> integrand{GenzGaussian(params)};
  const auto estimator = find_estimator("plain").make({});
  auto workspace = integrand.make_workspace();
  EstimatorScratch scratch;
  Counters counters;
  std::vector<double> estimates(256);
  std::uint32_t first = 0;
  for (auto _ : state) {
    BatchContext ctx{.key = 7, .first_sample = first, .sample_count = 256, .counters = &counters};
    estimator->estimate_batch(ctx, *workspace, scratch, estimates);
    benchmark::DoNotOptimize(estimates.data());
    first += 256;
  }
  state.SetItemsProcessed(state.iterations() * 256);
}
BENCHMARK(BM_PlainGenzGaussianBatch);

// Building P over a pool of M and drawing K from it, per camera sample: alias table against
// inverse CDF. Arguments: M, K.
template <DiscreteSamplerKind kKind>
void BM_BuildAndDraw(benchmark::State& state) {
  const auto m = static_cast<std::size_t>(state.range(0));
  const auto k = static_cast<int>(state.range(1));
  std::vector<double> pmf(m);
  RandomStream init({.key = 3});
  for (double& p : pmf) p = init.uniform();
  DiscreteSampler sampler;
  RandomStream rng({.key = 4});
  for (auto _ : state) {
    sampler.build(pmf, kKind);
    for (int i = 0; i < k; ++i) benchmark::DoNotOptimize(sampler.draw(rng));
  }
  state.SetItemsProcessed(state.iterations());
}
void resampling_sizes(benchmark::internal::Benchmark* b) {
  for (int m : {16, 256, 4096, 65536}) {
    for (int k : {4, 64}) b->Args({m, k});
  }
}
BENCHMARK(BM_BuildAndDraw<DiscreteSamplerKind::kAlias>)->Apply(resampling_sizes);
BENCHMARK(BM_BuildAndDraw<DiscreteSamplerKind::kCdf>)->Apply(resampling_sizes);

}  // namespace
}  // namespace pcbench

BENCHMARK_MAIN();
