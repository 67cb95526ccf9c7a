// The ray-rate ratio of every scene estimator (issue 27): how close a whole render iteration comes
// to Embree tracing the same rays alone.
//
// BM_RayRate/<estimator>/<scene> renders one iteration at 32×32 (BM_RayRate/{pcbpt,bdpt,pt}/
// <scene>/128 at 128×128) on one thread per benchmark iteration (replicates 0, 1, 2, …, as a run
// takes them) and counts its rays: rays_per_second. Before timing, replicate 0 is rendered once
// with the scene's ray log on (Scene::log_rays), which records every ray as Embree was given it, in
// order; after timing, those rays are traced again by rtcIntersect1/rtcOccluded1 alone on a BVH
// built here over the same triangles, in the same order and mix: embree_rays_per_second (thread CPU
// time). ratio = rays_per_second ÷ embree_rays_per_second is the share of a render's time that
// tracing would take if nothing else cost anything; 1 − ratio is what the estimator's own work
// costs. Both rates come from one benchmark run, side by side, as the targets ask.
//
// BM_ShadowPackets/<estimator>/<scene>/<width> asks what tracing shadow rays in batches would buy
// (issue 27's "rays in batches through Embree's packet interface"): the same logged rays, the
// closest-hit ones one by one, the shadow rays in packets of `width` consecutive ones
// (rtcOccluded4/8/16), against all of them one by one: packet_speedup is the rate of the
// first over the second. The log keeps the render's order, so a packet holds what one camera
// vertex and its neighbours in the pixel loop send; a renderer would need to gather as many.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "estimators/registry.h"
#include "estimators/scene/render_replicate.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/embree_scene.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kRayRateResolution = 32;
// pcbpt also at 128×128, where its cache points' tables (cache points × candidates, about 4 MB)
// no longer fit in the cache and their misses show; at 32×32 they do not.
constexpr std::uint32_t kLargeResolution = 128;
// The replay repeats the logged rays until it has run this long, for a stable rate.
constexpr double kReplaySeconds = 0.2;

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

RTCRay embree_ray(const LoggedRay& logged) {
  RTCRay ray{};
  ray.org_x = logged.origin[0];
  ray.org_y = logged.origin[1];
  ray.org_z = logged.origin[2];
  ray.tnear = logged.tnear;
  ray.dir_x = logged.direction[0];
  ray.dir_y = logged.direction[1];
  ray.dir_z = logged.direction[2];
  ray.tfar = logged.tfar;
  ray.mask = 0xFFFFFFFFu;
  return ray;
}

// Whether a closest-hit query of `ray` finds anything.
bool closest_hit(RTCScene scene, RTCIntersectContext& context, const RTCRay& ray) {
  RTCRayHit rh;
  rh.ray = ray;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &rh);
  return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

// Rays per CPU second of `pass` (which traces `rays` rays and returns how many hit), repeated
// until kReplaySeconds of this thread's CPU time have passed.
template <class Pass>
double replay_rate(std::size_t rays, Pass&& pass) {
  std::uint64_t traced = 0, hits = 0;
  const double start = thread_cpu_seconds();
  double elapsed = 0.0;
  while (elapsed < kReplaySeconds) {
    hits += pass();
    traced += rays;
    elapsed = thread_cpu_seconds() - start;
  }
  benchmark::DoNotOptimize(hits);
  return static_cast<double>(traced) / elapsed;
}

// Rays per CPU second of Embree alone over the logged rays, in their order.
double embree_rate(const std::vector<Triangle>& triangles, const std::vector<LoggedRay>& log) {
  const EmbreeScene raw(triangles);
  std::vector<RTCRay> rays;
  rays.reserve(log.size());
  for (const LoggedRay& logged : log) rays.push_back(embree_ray(logged));
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  return replay_rate(rays.size(), [&] {
    std::uint64_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (log[i].occlusion) {
        RTCRay ray = rays[i];
        rtcOccluded1(raw.handle(), &context, &ray);
        hits += ray.tfar < 0.0f;
      } else {
        hits += closest_hit(raw.handle(), context, rays[i]);
      }
    }
    return hits;
  });
}

std::unique_ptr<Scene> ray_rate_scene(const std::string& name,
                                      std::uint32_t resolution = kRayRateResolution) {
  auto description = built_in_scene(name);
  description->width = resolution;
  description->height = resolution;
  return std::make_unique<Scene>(std::move(*description));
}

// Every ray of replicate 0's render, as Embree was given it, and the render's counters.
TraceCounters log_replicate_rays(const Scene& scene, const SceneEstimator& estimator,
                                 std::vector<LoggedRay>& log) {
  scene.log_rays(&log);
  const TraceCounters logged = render_replicate(scene, estimator, 1, 0, 1).counters;
  scene.log_rays(nullptr);
  return logged;
}

void BM_RayRate(benchmark::State& state, const std::string& estimator, const std::string& name,
                std::uint32_t resolution) {
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const std::unique_ptr<Scene> scene_owner = ray_rate_scene(name, resolution);
  const Scene& scene = *scene_owner;
  const auto made = make_scene_estimator(estimator);

  std::vector<LoggedRay> log;
  const TraceCounters logged = log_replicate_rays(scene, *made, log);
  // Rays the trace counters leave out as set-up (pcbpt's cache paths), the same count each
  // iteration: counted per iteration so that the rate covers every ray traced.
  const std::uint64_t counted = logged.camera_rays + logged.light_rays + logged.shadow_rays;
  if (log.size() < counted) {
    state.SkipWithError("the ray log holds fewer rays than the trace counters");
    return;
  }
  const std::uint64_t setup_rays = log.size() - counted;

  TraceCounters counters;
  std::uint32_t replicate = 0;
  const double start = thread_cpu_seconds();
  for (auto _ : state) {
    const ReplicateImage out = render_replicate(scene, *made, 1, replicate++, 1);
    counters.add(out.counters);
    benchmark::DoNotOptimize(out.image.values.data());
  }
  const double render_seconds = thread_cpu_seconds() - start;
  const auto rays = static_cast<double>(counters.camera_rays + counters.light_rays +
                                        counters.shadow_rays + setup_rays * state.iterations());
  const double render_rate = rays / render_seconds;
  const double raw_rate = embree_rate(scene.description().triangles, log);
  state.counters["rays_per_second"] = render_rate;
  state.counters["embree_rays_per_second"] = raw_rate;
  state.counters["ratio"] = render_rate / raw_rate;
  state.counters["setup_rays"] = static_cast<double>(setup_rays);
  state.counters["shadow_share"] =
      static_cast<double>(logged.shadow_rays) / static_cast<double>(log.size());
}

// Rays per CPU second of Embree over the logged rays: the closest-hit rays one by one, then the
// shadow rays in packets of kWidth consecutive ones (a partial last packet masked).
template <std::size_t kWidth, class Packet, class Occluded>
double embree_packet_rate(const std::vector<Triangle>& triangles, const std::vector<LoggedRay>& log,
                          Occluded occluded) {
  const EmbreeScene raw(triangles);
  std::vector<RTCRay> closest, shadow;
  for (const LoggedRay& logged : log) {
    (logged.occlusion ? shadow : closest).push_back(embree_ray(logged));
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  return replay_rate(log.size(), [&] {
    std::uint64_t hits = 0;
    for (const RTCRay& ray : closest) hits += closest_hit(raw.handle(), context, ray);
    for (std::size_t first = 0; first < shadow.size(); first += kWidth) {
      const std::size_t count = std::min(kWidth, shadow.size() - first);
      alignas(64) int valid[kWidth];
      alignas(64) Packet packet;
      for (std::size_t k = 0; k < kWidth; ++k) {
        valid[k] = k < count ? -1 : 0;
        const RTCRay& ray = shadow[first + std::min(k, count - 1)];
        packet.org_x[k] = ray.org_x;
        packet.org_y[k] = ray.org_y;
        packet.org_z[k] = ray.org_z;
        packet.tnear[k] = ray.tnear;
        packet.dir_x[k] = ray.dir_x;
        packet.dir_y[k] = ray.dir_y;
        packet.dir_z[k] = ray.dir_z;
        packet.time[k] = ray.time;
        packet.tfar[k] = ray.tfar;
        packet.mask[k] = ray.mask;
        packet.id[k] = ray.id;
        packet.flags[k] = ray.flags;
      }
      occluded(valid, raw.handle(), &context, &packet);
      for (std::size_t k = 0; k < count; ++k) hits += packet.tfar[k] < 0.0f;
    }
    return hits;
  });
}

void BM_ShadowPackets(benchmark::State& state, const std::string& estimator,
                      const std::string& name, int width) {
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const std::unique_ptr<Scene> scene = ray_rate_scene(name);
  const auto made = make_scene_estimator(estimator);
  std::vector<LoggedRay> log;
  const TraceCounters logged = log_replicate_rays(*scene, *made, log);
  const std::vector<Triangle>& triangles = scene->description().triangles;
  double one_by_one = 0.0, packets = 0.0;
  for (auto _ : state) {
    one_by_one = embree_rate(triangles, log);
    if (width == 4) packets = embree_packet_rate<4, RTCRay4>(triangles, log, rtcOccluded4);
    if (width == 8) packets = embree_packet_rate<8, RTCRay8>(triangles, log, rtcOccluded8);
    if (width == 16) packets = embree_packet_rate<16, RTCRay16>(triangles, log, rtcOccluded16);
  }
  state.counters["packet_speedup"] = packets / one_by_one;
  state.counters["shadow_share"] =
      static_cast<double>(logged.shadow_rays) / static_cast<double>(log.size());
}

void register_ray_rate_benchmarks() {
  for (const std::string scene : {"cornell", "door-ajar"}) {
    for (const std::string estimator : {"bdpt", "pt", "lt", "lvc", "vc-all", "pcbpt"}) {
      benchmark::RegisterBenchmark(("BM_RayRate/" + estimator + "/" + scene).c_str(), BM_RayRate,
                                   estimator, scene, kRayRateResolution)
          ->Unit(benchmark::kMillisecond);
      for (const int width : {4, 8, 16}) {
        benchmark::RegisterBenchmark(
            ("BM_ShadowPackets/" + estimator + "/" + scene + "/" + std::to_string(width)).c_str(),
            BM_ShadowPackets, estimator, scene, width)
            ->Unit(benchmark::kMillisecond)
            ->Iterations(1);
      }
    }
  }
  // At 128×128: pcbpt, whose cache points' tables no longer fit in the cache there, and the
  // two estimators the renderer's lanes were built for first (BDPT's pool is W·H paths).
  for (const std::string scene : {"cornell", "door-ajar"}) {
    for (const std::string estimator : {"pcbpt", "bdpt", "pt"}) {
      benchmark::RegisterBenchmark(
          ("BM_RayRate/" + estimator + "/" + scene + "/" + std::to_string(kLargeResolution))
              .c_str(),
          BM_RayRate, estimator, scene, kLargeResolution)
          ->Unit(benchmark::kMillisecond);
    }
  }
}

[[maybe_unused]] const bool kRegistered = (register_ray_rate_benchmarks(), true);

}  // namespace
}  // namespace pcbench::scene
