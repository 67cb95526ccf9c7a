// The cost of one resampling candidate on a scene (issue 37, "candidates at arithmetic cost"):
// resample_emitters (estimators/scene/emitter_resampling.h) at the camera prefixes of 64 pixels'
// subpaths on many-lights, M candidates each (the benchmark's argument: 16, ris's default, and 4,
// which with 16 separates a candidate's own cost from what a resampling step costs once), with
// the unshadowed target (no shadow ray) and the visible one (a shadow ray per candidate).
// items_per_second counts candidates, so its inverse is the CPU time of one: an emitter point from
// three uniforms, its target value, the reservoir's step. The camera subpaths are traced outside
// the timed loop. One thread.
#include <benchmark/benchmark.h>

#include <memory>
#include <stdexcept>
#include <vector>

#include "base/rng.h"
#include "estimators/scene/emitter_resampling.h"
#include "estimators/scene/ris.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/render_services.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kResolution = 32;
constexpr std::uint32_t kPixels = 64;

void BM_EmitterCandidate(benchmark::State& state, EmitterTarget target) {
  const auto candidates = static_cast<std::uint32_t>(state.range(0));
  auto description = built_in_scene("many-lights");
  if (!description) throw std::runtime_error("no built-in scene many-lights");
  description->width = kResolution;
  description->height = kResolution;
  const Scene scene(std::move(*description));
  const std::uint32_t max_length = scene.description().max_length;
  const StrategyCounts counts = next_event_counts(candidates);
  const RenderServices services(scene, counts, 5, 0, nullptr);

  std::vector<std::vector<PathVertex>> paths(kPixels);
  TraceCounters setup;
  for (std::uint32_t j = 0; j < kPixels; ++j) {
    RandomStream rng({.key = 5, .purpose = StreamPurpose::kCameraPath, .sample = j});
    const std::uint32_t pixel = (j * 37) % (kResolution * kResolution);
    trace_camera_path(scene, pixel % kResolution + rng.uniform(),
                      pixel / kResolution + rng.uniform(), rng, max_length, paths[j], setup);
  }
  struct Prefix {
    std::uint32_t path, t;
  };
  std::vector<Prefix> prefixes;
  for (std::uint32_t j = 0; j < kPixels; ++j) {
    for (std::uint32_t t = 2; t <= paths[j].size() && t < max_length; ++t)
      prefixes.push_back({j, t});
  }
  if (prefixes.empty()) throw std::runtime_error("no camera prefix to resample at");

  RandomStream camera({.key = 6, .purpose = StreamPurpose::kCameraPath});
  RandomStream draws({.key = 6, .purpose = StreamPurpose::kResampling});
  TraceCounters counters;
  std::size_t i = 0;
  for (auto _ : state) {
    const Prefix& p = prefixes[i];
    CameraPrefix prefix{.pixel = 0,
                        .vertices = std::span<const PathVertex>(paths[p.path]).first(p.t),
                        .max_s = max_length + 1 - p.t,
                        .camera = camera,
                        .draws = draws,
                        .counters = counters};
    const EmitterSample kept = resample_emitters(services, prefix, candidates, target);
    benchmark::DoNotOptimize(kept.contribution_weight);
    if (++i == prefixes.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations() * candidates);
  state.counters["shadow_rays_per_candidate"] =
      static_cast<double>(counters.shadow_rays) /
      static_cast<double>(state.iterations() * candidates);
}
BENCHMARK_CAPTURE(BM_EmitterCandidate, unshadowed, EmitterTarget::kUnshadowed)->Arg(16)->Arg(4);
BENCHMARK_CAPTURE(BM_EmitterCandidate, visible, EmitterTarget::kVisible)->Arg(16)->Arg(4);

}  // namespace
}  // namespace pcbench::scene
