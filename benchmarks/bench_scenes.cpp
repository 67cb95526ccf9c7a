// Scene microbenchmarks: the raw Embree rate for BDPT's own rays against our wrapper (Scene), the
// subpath walks, one connection, and whole render iterations with their rays per second.
//
// The rays are BDPT's: one iteration of bdpt at 32×32 is replayed with the public walks and
// connect() (the same streams as integrands/scenes/render_services.cpp), and every closest-hit
// segment and every shadow ray it traces is recorded, outside the timed loops. Walks that leave the
// scene have no end point and are not recorded ("missed" counters say how many). The raw rate
// traces the same rays through an RTCScene built here from the same float geometry as Scene's.
//
// The BDPT-vs-raw target: rays_per_second of BM_RenderIteration/bdpt against the weighted
// harmonic mean of BM_EmbreeRawClosestHit and BM_EmbreeRawOcclusion on cornell, weighted by the
// closest-hit and shadow ray counts BM_RenderIteration/bdpt reports. Every benchmark here runs
// on one thread (tbb::global_control).
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/rng.h"
#include "estimators/registry.h"
#include "estimators/scene/render_replicate.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/connection.h"
#include "integrands/scenes/embree_scene.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kResolution = 32;

std::unique_ptr<Scene> make_scene(const std::string& name) {
  auto description = built_in_scene(name);
  if (!description) throw std::runtime_error("no built-in scene " + name);
  description->width = kResolution;
  description->height = kResolution;
  return std::make_unique<Scene>(std::move(*description));
}

struct ClosestRay {
  Vec3 origin, direction;
};
struct ShadowRay {
  Vec3 a, b;
};

// A scene with the rays one bdpt iteration traces in it.
struct RecordedScene {
  std::unique_ptr<Scene> scene;
  std::vector<ClosestRay> closest;
  std::vector<ShadowRay> shadow;
  TraceCounters counters;   // what the replay counted (rays that left the scene included)
  TraceCounters reference;  // what render_replicate counts for the same iteration
};

void record_segments(const std::vector<PathVertex>& path, std::vector<ClosestRay>& out) {
  for (std::size_t i = 1; i < path.size(); ++i) {
    out.push_back({path[i - 1].position, normalize(path[i].position - path[i - 1].position)});
  }
}

// connect() with visibility, recording its shadow ray when it traced one.
void connect_recording(const Scene& scene, std::span<const PathVertex> light,
                       std::span<const PathVertex> camera, const StrategyCounts& counts,
                       TraceCounters& counters, std::vector<ShadowRay>& out) {
  const std::uint64_t before = counters.shadow_rays;
  benchmark::DoNotOptimize(connect(scene, light, camera, counts, {}, counters));
  if (counters.shadow_rays != before) {
    out.push_back({light.back().position, camera.back().position});
  }
}

// Replays iteration 0 of bdpt (estimators/scene/plain.cpp through render_replicate).
RecordedScene record_bdpt(const std::string& name) {
  RecordedScene r;
  r.scene = make_scene(name);
  const Scene& scene = *r.scene;
  const auto bdpt = make_scene_estimator("bdpt");
  const StrategyCounts counts = bdpt->strategy_counts(scene);
  const std::uint32_t w = scene.description().width, h = scene.description().height;
  const std::uint32_t max_length = scene.description().max_length;
  auto stream = [](StreamPurpose purpose, std::uint32_t path) {
    return StreamId{.key = 1, .replicate = 0, .purpose = purpose, .sample = 0, .path = path};
  };
  std::vector<std::vector<PathVertex>> pool(std::size_t{w} * h);
  for (std::uint32_t j = 0; j < pool.size(); ++j) {
    RandomStream rng(stream(StreamPurpose::kLightPool, j));
    trace_light_path(scene, rng, max_length, pool[j], r.counters);
    record_segments(pool[j], r.closest);
  }
  PathVertex camera_vertex;
  camera_vertex.kind = VertexKind::kCamera;
  camera_vertex.position = scene.camera().position();
  camera_vertex.beta = {1.0, 1.0, 1.0};
  for (const auto& path : pool) {
    for (std::uint32_t s = 1; s <= path.size() && s <= max_length; ++s) {
      connect_recording(scene, std::span(path).first(s), std::span(&camera_vertex, 1), counts,
                        r.counters, r.shadow);
    }
  }
  std::vector<PathVertex> camera;
  for (std::uint32_t pixel = 0; pixel < w * h; ++pixel) {
    RandomStream rng(stream(StreamPurpose::kCameraPath, pixel));
    const double fx = pixel % w + rng.uniform(), fy = pixel / w + rng.uniform();
    trace_camera_path(scene, fx, fy, rng, max_length, camera, r.counters);
    record_segments(camera, r.closest);
    const auto& path = pool[pixel];
    for (std::uint32_t t = 2; t <= camera.size() && t <= max_length; ++t) {
      const std::uint32_t max_s = max_length + 1 - t;
      for (std::uint32_t s = 1; s <= std::min<std::uint32_t>(max_s, path.size()); ++s) {
        connect_recording(scene, std::span(path).first(s), std::span(camera).first(t), counts,
                          r.counters, r.shadow);
      }
    }
  }
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  r.reference = render_replicate(scene, *bdpt, 1, 0, 1).counters;
  return r;
}

const RecordedScene& recorded(const std::string& name) {
  static std::map<std::string, RecordedScene> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, record_bdpt(name)).first;
  return it->second;
}

// The timed loop of every ray benchmark: `trace(i)` for ray i of `count`, in turn and round
// again, summing what it returns (hits, or rays blocked) so that no trace is optimised away.
template <class Trace>
void time_rays(benchmark::State& state, std::size_t count, Trace trace) {
  std::size_t i = 0;
  std::uint64_t counted = 0;
  for (auto _ : state) {
    counted += trace(i);
    if (++i == count) i = 0;
  }
  benchmark::DoNotOptimize(counted);
  state.SetItemsProcessed(state.iterations());
}

// The raw rate: an EmbreeScene of our own over the same float triangles, and the recorded rays
// in float, ready for rtcIntersect1 / rtcOccluded1.

RTCRay float_ray(const Vec3& origin, const Vec3& direction, double tnear, double tfar) {
  RTCRay ray{};
  ray.org_x = static_cast<float>(origin.x);
  ray.org_y = static_cast<float>(origin.y);
  ray.org_z = static_cast<float>(origin.z);
  ray.dir_x = static_cast<float>(direction.x);
  ray.dir_y = static_cast<float>(direction.y);
  ray.dir_z = static_cast<float>(direction.z);
  ray.tnear = static_cast<float>(tnear);
  ray.tfar = static_cast<float>(tfar);
  ray.mask = 0xFFFFFFFFu;
  return ray;
}

void add_ray_counters(benchmark::State& state, const RecordedScene& r) {
  state.counters["closest_rays"] = static_cast<double>(r.closest.size());
  state.counters["shadow_rays"] = static_cast<double>(r.shadow.size());
  state.counters["missed"] =
      static_cast<double>(r.counters.camera_rays + r.counters.light_rays - r.closest.size());
  // The replay's fidelity: render_replicate's own counts for the same key and iteration.
  state.counters["render_closest"] =
      static_cast<double>(r.reference.camera_rays + r.reference.light_rays);
  state.counters["render_shadow"] = static_cast<double>(r.reference.shadow_rays);
}

void BM_EmbreeRawClosestHit(benchmark::State& state, const std::string& name) {
  const RecordedScene& r = recorded(name);
  const EmbreeScene raw(r.scene->description().triangles);
  std::vector<RTCRay> rays;
  for (const ClosestRay& c : r.closest) {
    rays.push_back(float_ray(c.origin, c.direction, r.scene->epsilon(), 1e30));
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  time_rays(state, rays.size(), [&](std::size_t i) {
    RTCRayHit rh;
    rh.ray = rays[i];
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(raw.handle(), &context, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  });
  add_ray_counters(state, r);
}

void BM_EmbreeRawOcclusion(benchmark::State& state, const std::string& name) {
  const RecordedScene& r = recorded(name);
  const EmbreeScene raw(r.scene->description().triangles);
  const double epsilon = r.scene->epsilon();
  std::vector<RTCRay> rays;
  for (const ShadowRay& s : r.shadow) {
    const Vec3 d = s.b - s.a;
    const double distance = length(d);
    rays.push_back(float_ray(s.a, d / distance, epsilon, distance - epsilon));
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  time_rays(state, rays.size(), [&](std::size_t i) {
    RTCRay ray = rays[i];
    rtcOccluded1(raw.handle(), &context, &ray);
    return ray.tfar < 0.0f;
  });
  add_ray_counters(state, r);
}

// Diagnostic: the raw call, but the ray filled field by field from the double ray (zeroed
// RTCRayHit, scalar float conversions), as Scene::intersect filled it before fill_ray: Embree's
// 16-byte loads of a ray just written float by float miss store-to-load forwarding.
void BM_EmbreeRawClosestHitFilled(benchmark::State& state, const std::string& name) {
  const RecordedScene& r = recorded(name);
  const EmbreeScene raw(r.scene->description().triangles);
  const auto tnear = static_cast<float>(r.scene->epsilon());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  time_rays(state, r.closest.size(), [&](std::size_t i) {
    const ClosestRay& c = r.closest[i];
    RTCRayHit rh{};
    rh.ray.org_x = static_cast<float>(c.origin.x);
    rh.ray.org_y = static_cast<float>(c.origin.y);
    rh.ray.org_z = static_cast<float>(c.origin.z);
    rh.ray.dir_x = static_cast<float>(c.direction.x);
    rh.ray.dir_y = static_cast<float>(c.direction.y);
    rh.ray.dir_z = static_cast<float>(c.direction.z);
    rh.ray.tnear = tnear;
    rh.ray.tfar = 1e30f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(raw.handle(), &context, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  });
}

// The same closest-hit rays through our wrapper (double in, float to Embree, distance recomputed).
void BM_SceneIntersect(benchmark::State& state, const std::string& name) {
  const RecordedScene& r = recorded(name);
  time_rays(state, r.closest.size(), [&](std::size_t i) {
    Hit hit;
    const bool hits = r.scene->intersect(r.closest[i].origin, r.closest[i].direction, hit);
    benchmark::DoNotOptimize(hit);
    return hits;
  });
}

// The same shadow rays through Scene::occluded (double end points, normalisation in double).
void BM_SceneOccluded(benchmark::State& state, const std::string& name) {
  const RecordedScene& r = recorded(name);
  time_rays(state, r.shadow.size(),
            [&](std::size_t i) { return r.scene->occluded(r.shadow[i].a, r.shadow[i].b); });
}

void register_ray_benchmarks() {
  for (const std::string name : {"cornell", "door-ajar"}) {
    benchmark::RegisterBenchmark(("BM_EmbreeRawClosestHit/" + name).c_str(), BM_EmbreeRawClosestHit,
                                 name);
    benchmark::RegisterBenchmark(("BM_EmbreeRawOcclusion/" + name).c_str(), BM_EmbreeRawOcclusion,
                                 name);
    benchmark::RegisterBenchmark(("BM_EmbreeRawClosestHitFilled/" + name).c_str(),
                                 BM_EmbreeRawClosestHitFilled, name);
    benchmark::RegisterBenchmark(("BM_SceneIntersect/" + name).c_str(), BM_SceneIntersect, name);
    benchmark::RegisterBenchmark(("BM_SceneOccluded/" + name).c_str(), BM_SceneOccluded, name);
  }
}

// Subpaths on cornell at its max_length (5), the n-th from `trace(scene, n, max_length, path,
// counters)`. items_per_second: subpaths; rays_per_second: the rays of the kind `rays` counts.
template <class Trace>
void time_subpaths(benchmark::State& state, Trace trace, std::uint64_t TraceCounters::*rays) {
  const auto scene = make_scene("cornell");
  const std::uint32_t max_length = scene->description().max_length;
  std::vector<PathVertex> path;
  TraceCounters counters;
  std::uint32_t n = 0;
  for (auto _ : state) {
    trace(*scene, n++, max_length, path, counters);
    benchmark::DoNotOptimize(path.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["rays_per_second"] =
      benchmark::Counter(static_cast<double>(counters.*rays), benchmark::Counter::kIsRate);
}

void BM_CameraSubpath(benchmark::State& state) {
  time_subpaths(
      state,
      [](const Scene& scene, std::uint32_t n, std::uint32_t max_length,
         std::vector<PathVertex>& path, TraceCounters& counters) {
        RandomStream rng({.key = 2, .purpose = StreamPurpose::kCameraPath, .sample = n});
        const std::uint32_t pixel = n % (kResolution * kResolution);
        trace_camera_path(scene, pixel % kResolution + rng.uniform(),
                          pixel / kResolution + rng.uniform(), rng, max_length, path, counters);
      },
      &TraceCounters::camera_rays);
}
BENCHMARK(BM_CameraSubpath);

void BM_LightSubpath(benchmark::State& state) {
  time_subpaths(
      state,
      [](const Scene& scene, std::uint32_t n, std::uint32_t max_length,
         std::vector<PathVertex>& path, TraceCounters& counters) {
        RandomStream rng({.key = 3, .purpose = StreamPurpose::kLightPool, .path = n});
        trace_light_path(scene, rng, max_length, path, counters);
      },
      &TraceCounters::light_rays);
}
BENCHMARK(BM_LightSubpath);

// One connect() between a camera prefix (t >= 2) and a light prefix (s >= 1), visibility on,
// cycling over the (s, t) strategies bdpt evaluates for 256 pixel/light-path pairs on cornell.
// items_per_second: connect calls; shadow_fraction: the share that traced a shadow ray.
void BM_Connection(benchmark::State& state) {
  const auto scene = make_scene("cornell");
  const std::uint32_t max_length = scene->description().max_length;
  const StrategyCounts counts = make_scene_estimator("plain")->strategy_counts(*scene);
  constexpr std::uint32_t kPairs = 256;
  std::vector<std::vector<PathVertex>> light(kPairs), camera(kPairs);
  struct Job {
    std::uint32_t pair, s, t;
  };
  std::vector<Job> jobs;
  TraceCounters setup;
  for (std::uint32_t j = 0; j < kPairs; ++j) {
    RandomStream light_rng({.key = 4, .purpose = StreamPurpose::kLightPool, .path = j});
    trace_light_path(*scene, light_rng, max_length, light[j], setup);
    RandomStream camera_rng({.key = 4, .purpose = StreamPurpose::kCameraPath, .sample = j});
    const std::uint32_t pixel = (j * 37) % (kResolution * kResolution);
    trace_camera_path(*scene, pixel % kResolution + camera_rng.uniform(),
                      pixel / kResolution + camera_rng.uniform(), camera_rng, max_length, camera[j],
                      setup);
    for (std::uint32_t t = 2; t <= camera[j].size() && t <= max_length; ++t) {
      for (std::uint32_t s = 1; s <= std::min<std::uint32_t>(max_length + 1 - t, light[j].size());
           ++s) {
        jobs.push_back({j, s, t});
      }
    }
  }
  TraceCounters counters;
  std::size_t i = 0;
  for (auto _ : state) {
    const Job& job = jobs[i];
    benchmark::DoNotOptimize(connect(*scene, std::span(light[job.pair]).first(job.s),
                                     std::span(camera[job.pair]).first(job.t), counts, {},
                                     counters));
    if (++i == jobs.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["shadow_fraction"] =
      static_cast<double>(counters.shadow_rays) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_Connection);

// One replicate of one iteration on cornell at 32×32, one thread. rays_per_second counts camera,
// light and shadow rays; the per-iteration counts give the weights of the raw-rate comparison.
void BM_RenderIteration(benchmark::State& state, const std::string& estimator) {
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const auto scene = make_scene("cornell");
  const auto made = make_scene_estimator(estimator);
  TraceCounters counters;
  std::uint32_t replicate = 0;
  for (auto _ : state) {
    const ReplicateImage out = render_replicate(*scene, *made, 1, replicate++, 1);
    counters.add(out.counters);
    benchmark::DoNotOptimize(out.image.values.data());
  }
  const double closest = static_cast<double>(counters.camera_rays + counters.light_rays);
  const double shadow = static_cast<double>(counters.shadow_rays);
  state.counters["rays_per_second"] =
      benchmark::Counter(closest + shadow, benchmark::Counter::kIsRate);
  state.counters["closest_rays"] = benchmark::Counter(closest, benchmark::Counter::kAvgIterations);
  state.counters["shadow_rays"] = benchmark::Counter(shadow, benchmark::Counter::kAvgIterations);
}
BENCHMARK_CAPTURE(BM_RenderIteration, bdpt, std::string("bdpt"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderIteration, pt, std::string("pt"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderIteration, pcbpt, std::string("pcbpt"))->Unit(benchmark::kMillisecond);

// Registered before main() runs, next to bench_main.cpp's static registrations.
[[maybe_unused]] const bool kRegistered = (register_ray_benchmarks(), true);

}  // namespace
}  // namespace pcbench::scene
