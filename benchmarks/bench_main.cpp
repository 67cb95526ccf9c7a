// Microbenchmarks (Google Benchmark). Run: build/release/pcbench_bench [--benchmark_filter=RE]
#include <benchmark/benchmark.h>

#include <oneapi/tbb/global_control.h>

#include <array>
#include <numeric>

#include "base/discrete_sampler.h"
#include "base/philox_lanes.h"
#include "base/rng.h"
#include "base/tally.h"
#include "estimators/registry.h"
#include "estimators/resampling_step.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "integrands/genz.h"
#include "integrands/point_integrand.h"
#include "integrands/registry.h"

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

// Blocks of 256 consecutive paths' first counters, as PointWorkspace::sample_paths makes them.
void BM_PhiloxMany(benchmark::State& state) {
  std::vector<PhiloxCounter> counters(256), out(256);
  std::uint32_t sample = 0;
  for (auto _ : state) {
    for (std::uint32_t j = 0; j < counters.size(); ++j) counters[j] = {0, j, sample, 0x01000000u};
    philox4x32_10_many(counters, {0x12345678u, 0x9ABCDEF0u}, out);
    benchmark::DoNotOptimize(out.data());
    ++sample;
  }
  state.SetItemsProcessed(state.iterations() * 256);
}
BENCHMARK(BM_PhiloxMany);

// The same, with each way of computing blocks this machine has (philox4x32_10_many takes the
// widest): the ratios side by side in one run.
void BM_PhiloxManyLanes(benchmark::State& state, PhiloxLanes lanes) {
  if (!philox_lanes_supported(lanes)) {
    state.SkipWithError("not supported on this CPU");
    return;
  }
  std::vector<PhiloxCounter> counters(256), out(256);
  std::uint32_t sample = 0;
  for (auto _ : state) {
    for (std::uint32_t j = 0; j < counters.size(); ++j) counters[j] = {0, j, sample, 0x01000000u};
    philox4x32_10_many_with(lanes, counters, {0x12345678u, 0x9ABCDEF0u}, out);
    benchmark::DoNotOptimize(out.data());
    ++sample;
  }
  state.SetItemsProcessed(state.iterations() * 256);
}
BENCHMARK_CAPTURE(BM_PhiloxManyLanes, scalar, PhiloxLanes::kScalar);
BENCHMARK_CAPTURE(BM_PhiloxManyLanes, avx2, PhiloxLanes::kAvx2);
BENCHMARK_CAPTURE(BM_PhiloxManyLanes, avx512, PhiloxLanes::kAvx512);

// A few blocks at a time, as a resampling step's streams ask for them (three uniforms a
// candidate, one per acceptance), each way side by side: where a padded tail of a group stops
// paying against one block at a time (kScalarTail in base/rng.cpp).
void BM_PhiloxFew(benchmark::State& state, PhiloxLanes lanes) {
  if (!philox_lanes_supported(lanes)) {
    state.SkipWithError("not supported on this CPU");
    return;
  }
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<PhiloxCounter> counters(n), out(n);
  std::uint32_t sample = 0;
  for (auto _ : state) {
    for (std::uint32_t j = 0; j < n; ++j) counters[j] = {j, 7, sample, 0x01000000u};
    philox4x32_10_many_with(lanes, counters, {0x12345678u, 0x9ABCDEF0u}, out);
    benchmark::DoNotOptimize(out.data());
    ++sample;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}
BENCHMARK_CAPTURE(BM_PhiloxFew, scalar, PhiloxLanes::kScalar)->DenseRange(1, 4)->Arg(8);
BENCHMARK_CAPTURE(BM_PhiloxFew, avx2, PhiloxLanes::kAvx2)->DenseRange(1, 4)->Arg(8);
BENCHMARK_CAPTURE(BM_PhiloxFew, avx512, PhiloxLanes::kAvx512)->DenseRange(1, 4)->Arg(8)->Arg(12);

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

// genz-gaussian at its defaults (1 + 1 dimensions), the cheap integrand of the overhead benchmarks.
GenzGaussian default_genz_gaussian() {
  return GenzGaussian(resolve_params(GenzGaussian::params(), {}, "genz-gaussian"));
}

// The plain estimator on a cheap integrand, one batch per iteration.
void BM_PlainGenzGaussianBatch(benchmark::State& state) {
  const PointIntegrand<GenzGaussian> integrand{default_genz_gaussian()};
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

// f of 256 (light, camera) pairs through an integrand's workspace, for every analytic integrand
// with default parameters (registered at start-up from the registry).
void connect_benchmark(benchmark::State& state, const IntegrandEntry* entry) {
  const auto integrand = entry->make(resolve_params(entry->params, {}, entry->name));
  auto workspace = integrand->make_workspace();
  workspace->sample_paths(PathSide::kLight, {.key = 1}, 0, 256, 1);
  workspace->sample_paths(PathSide::kCamera, {.key = 2}, 0, 256, 1);
  std::vector<PathPair> pairs(256);
  for (std::uint32_t i = 0; i < 256; ++i) pairs[i] = {.light = i, .camera = (i * 7) % 256};
  std::vector<double> values(256);
  for (auto _ : state) {
    workspace->connect(pairs, values);
    benchmark::DoNotOptimize(values.data());
  }
  state.SetItemsProcessed(state.iterations() * 256);
}

// Sampling a fresh pool of M = 16 light paths for each of 256 camera samples.
void BM_SamplePool(benchmark::State& state) {
  const IntegrandEntry& entry = find_integrand("genz-gaussian");
  const auto integrand = entry.make(resolve_params(entry.params, {}, entry.name));
  auto workspace = integrand->make_workspace();
  std::uint32_t first = 0;
  for (auto _ : state) {
    workspace->clear();
    workspace->sample_paths(PathSide::kLight, {.key = 1}, first, 256, 16);
    first += 256;
  }
  state.SetItemsProcessed(state.iterations() * 256 * 16);
}
BENCHMARK(BM_SamplePool);

// The probabilistic-connections target (issue 6): per camera sample, evaluating the M
// importances, building P and drawing K = 4 (BM_ImportanceStep) against one pass that evaluates
// and sums the M importances (BM_ImportanceSum), on blocker (the unoccluded kernel). Argument: M.
struct ImportanceFixture {
  explicit ImportanceFixture(std::uint32_t m) : pairs(m), importance(m) {
    const IntegrandEntry& entry = find_integrand("blocker");
    integrand = entry.make(resolve_params(entry.params, {}, entry.name));
    workspace = integrand->make_workspace();
    workspace->sample_paths(PathSide::kLight, {.key = 1}, 0, 1, m);
    workspace->sample_paths(PathSide::kCamera, {.key = 2}, 0, 1, 1);
    for (std::uint32_t j = 0; j < m; ++j) pairs[j] = {.light = j, .camera = 0};
  }
  std::unique_ptr<Integrand> integrand;
  std::unique_ptr<PathWorkspace> workspace;
  std::vector<PathPair> pairs;
  std::vector<double> importance;
};

void BM_ImportanceSum(benchmark::State& state) {
  ImportanceFixture f(static_cast<std::uint32_t>(state.range(0)));
  for (auto _ : state) {
    f.workspace->importance(f.pairs, f.importance);
    benchmark::DoNotOptimize(std::accumulate(f.importance.begin(), f.importance.end(), 0.0));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ImportanceSum)->Arg(16)->Arg(256)->Arg(4096)->Arg(65536);

void BM_ImportanceStep(benchmark::State& state) {
  const auto m = static_cast<std::uint32_t>(state.range(0));
  ImportanceFixture f(m);
  const ResamplingStep step(
      {.M = m, .K = 4, .selection = Selection::kImportance, .scheme = DrawScheme::kIndependent});
  std::vector<double> pmf;
  DiscreteSampler sampler;
  std::vector<std::uint32_t> draws;
  std::vector<Term> terms;
  StreamId stream{.key = 5};
  for (auto _ : state) {
    f.workspace->importance(f.pairs, f.importance);
    terms.clear();
    ++stream.sample;
    RandomStream rng(stream);
    step.choose({.importance = f.importance}, rng, pmf, sampler, draws, terms);
    benchmark::DoNotOptimize(terms.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ImportanceStep)->Arg(16)->Arg(256)->Arg(4096)->Arg(65536);

// The harness-overhead target (issue 6): `plain` on genz-gaussian through the whole runner (one
// thread, 2 replicates x 2^18 samples) against a hand-written loop with the same integrand,
// generator streams and accumulation. Compare items_per_second (samples per second).
constexpr std::uint64_t kOverheadSamples = 1u << 18;

void BM_HarnessPlainGenzGaussian(benchmark::State& state) {
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const RunPlan plan = plan_runs({GridRequest{.estimators = {"plain"},
                                              .integrands = {"genz-gaussian"},
                                              .samples = kOverheadSamples,
                                              .replicates = 2,
                                              .where = "benchmark"}},
                                 {})[0];
  for (auto _ : state) benchmark::DoNotOptimize(execute_run(plan, {.seed = 1}).replicates.data());
  state.SetItemsProcessed(state.iterations() * 2 * kOverheadSamples);
}
BENCHMARK(BM_HarnessPlainGenzGaussian)->Unit(benchmark::kMillisecond);

void BM_HandWrittenPlainGenzGaussian(benchmark::State& state) {
  const GenzGaussian model = default_genz_gaussian();
  // The streams' first blocks come 64 samples at a time from philox4x32_10_many, as the
  // harness's workspaces take them, so that the two loops differ only in the harness around them.
  constexpr std::uint32_t kGroup = 64;
  std::array<PhiloxCounter, 2 * kGroup> counters, blocks;
  for (auto _ : state) {
    for (std::uint32_t replicate = 0; replicate < 2; ++replicate) {
      Tally tally;
      for (std::uint32_t first = 0; first < kOverheadSamples; first += kGroup) {
        auto id = [&](StreamPurpose purpose, std::uint32_t s) {
          return StreamId{.key = 9, .replicate = replicate, .purpose = purpose, .sample = s};
        };
        for (std::uint32_t g = 0; g < kGroup; ++g) {
          counters[g] = RandomStream::first_counter(id(StreamPurpose::kLightPool, first + g));
          counters[kGroup + g] =
              RandomStream::first_counter(id(StreamPurpose::kCameraPath, first + g));
        }
        philox4x32_10_many(counters, RandomStream::key_of(id(StreamPurpose::kLightPool, 0)),
                           blocks);
        for (std::uint32_t g = 0; g < kGroup; ++g) {
          RandomStream light(id(StreamPurpose::kLightPool, first + g), blocks[g]);
          RandomStream camera(id(StreamPurpose::kCameraPath, first + g), blocks[kGroup + g]);
          const double x = light.uniform();
          const double y = camera.uniform();
          tally.add(model.f(&x, &y), first + g);
        }
      }
      benchmark::DoNotOptimize(tally.mean());
    }
  }
  state.SetItemsProcessed(state.iterations() * 2 * kOverheadSamples);
}
BENCHMARK(BM_HandWrittenPlainGenzGaussian)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pcbench

int main(int argc, char** argv) {
  for (const pcbench::IntegrandEntry& entry : pcbench::integrand_registry()) {
    const bool required = std::any_of(entry.params.begin(), entry.params.end(),
                                      [](const pcbench::ParamSpec& p) { return p.required; });
    if (required) continue;
    benchmark::RegisterBenchmark(("BM_Connect/" + entry.name).c_str(), pcbench::connect_benchmark,
                                 &entry);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
