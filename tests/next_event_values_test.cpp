// Resampling candidates at their own cost against the one-by-one code they stand in for, on
// every built-in scene: NextEventValues gives connect()'s unweighted, unoccluded next-event
// value to the bit with the same counters, and resample_emitters (candidates in batches, their
// uniforms drawn together, the visible target's shadow rays in packets) keeps the candidate,
// contribution weight and counters of the candidates weighed one at a time through connect()
// and chosen by the same reservoir step. What the images owe to these is checked whole by
// ctest estimators.hashes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "base/rng.h"
#include "estimators/reservoir.h"
#include "estimators/scene/emitter_resampling.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/connection.h"
#include "integrands/scenes/next_event_values.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/render_services.h"
#include "integrands/scenes/scene.h"
#include "test_support.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kResolution = 12;

Scene built_in(const std::string& name) {
  SceneDescription d = *built_in_scene(name);
  d.width = d.height = kResolution;
  return Scene(std::move(d));
}

std::vector<std::vector<PathVertex>> camera_paths(const Scene& scene) {
  std::vector<std::vector<PathVertex>> paths(kResolution * kResolution);
  TraceCounters counters;
  for (std::uint32_t p = 0; p < paths.size(); ++p) {
    RandomStream rng({.key = 0x7e57, .purpose = StreamPurpose::kCameraPath, .path = p});
    const double fx = p % kResolution + rng.uniform(), fy = p / kResolution + rng.uniform();
    trace_camera_path(scene, fx, fy, rng, scene.description().max_length, paths[p], counters);
  }
  return paths;
}

bool same_bits(const Rgb& a, const Rgb& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

bool same_counters(const TraceCounters& a, const TraceCounters& b) {
  return a.connections == b.connections && a.shadow_rays == b.shadow_rays &&
         a.occluded == b.occluded && a.skipped_zero == b.skipped_zero &&
         a.skipped_convex == b.skipped_convex;
}

class NextEventValuesOn : public ::testing::TestWithParam<std::string> {};

// With the counts of an estimator that takes next events, and of one that does not (no value,
// nothing counted).
TEST_P(NextEventValuesOn, EachValueIsConnectsUnweightedUnoccludedValue) {
  const Scene scene = built_in(GetParam());
  const auto paths = camera_paths(scene);
  std::size_t compared = 0, nonzero = 0;
  for (const double next_event : {1.0, 0.0}) {
    const StrategyCounts counts{.next_event = next_event};
    for (std::uint32_t p = 0; p < paths.size(); ++p) {
      RandomStream rng({.key = 0x7e57, .purpose = StreamPurpose::kEstimatorAux, .path = p});
      for (std::uint32_t t = 2; t <= paths[p].size(); ++t) {
        const std::span<const PathVertex> camera = std::span(paths[p]).first(t);
        const NextEventValues values(scene, camera, counts);
        for (int k = 0; k < 8; ++k) {
          const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
          const EmitterPoint x = scene.emitters().sample(u0, u1, u2);
          const PathVertex vertex = emitter_vertex(x);
          TraceCounters fast, reference;
          const NextEventValue got = values.value(x, fast);
          const Rgb want = connect(scene, std::span(&vertex, 1), camera, counts,
                                   {.visibility = false, .weighted = false}, reference);
          ASSERT_TRUE(same_bits(got.value, want)) << "pixel " << p << " t " << t << " k " << k;
          ASSERT_TRUE(same_counters(fast, reference)) << "pixel " << p << " t " << t;
          ++compared;
          if (!want.is_black()) ++nonzero;
        }
      }
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_GT(nonzero, 100u);  // the comparison saw values, not only zeros
}

// The candidates one at a time through connect(), as resample_emitters weighed them before its
// lanes, the reservoir's choice taken as resample_emitters takes it (Reservoir::offer_batch, a
// batch of EmitterPoints::kCapacity at a time, whose distribution ReservoirSampling.* test).
EmitterSample resample_one_by_one(const RenderServices& services, CameraPrefix& prefix,
                                  std::uint32_t candidates, EmitterTarget target) {
  constexpr std::uint32_t kBatch = EmitterPoints::kCapacity;
  Reservoir reservoir;
  EmitterSample kept;
  for (std::uint32_t first = 0; first < candidates; first += kBatch) {
    const std::uint32_t n = std::min(kBatch, candidates - first);
    std::vector<PathVertex> points;
    std::vector<Rgb> values;
    std::vector<double> weights;
    for (std::uint32_t i = 0; i < n; ++i) {
      points.push_back(sample_emitter_vertex(services.scene(), prefix.camera));
      values.push_back(services.connect(
          std::span(&points.back(), 1), prefix.vertices,
          {.visibility = target == EmitterTarget::kVisible, .weighted = false}, prefix.counters));
      weights.push_back(values.back().max_channel());
    }
    const std::uint32_t before = reservoir.kept();
    reservoir.offer_batch(first, weights, prefix.draws);
    if (reservoir.kept() != before) {
      const std::uint32_t j = reservoir.kept() - first;
      kept.point = points[j];
      kept.at_owner = {values[j], weights[j] * points[j].pdf_fwd};
    }
  }
  if (!reservoir.empty()) {
    kept.contribution_weight =
        reservoir.weight_sum() / (static_cast<double>(candidates) * kept.at_owner.density);
  }
  return kept;
}

TEST_P(NextEventValuesOn, BatchedResamplingKeepsWhatOneByOneKeeps) {
  const Scene scene = built_in(GetParam());
  const auto paths = camera_paths(scene);
  const StrategyCounts counts{.next_event = 16.0};
  const RenderServices services(scene, counts, 0x7e57, 1, nullptr);
  std::size_t kept_some = 0;
  for (const EmitterTarget target : {EmitterTarget::kUnshadowed, EmitterTarget::kVisible}) {
    for (const std::uint32_t candidates : {1u, 16u, 64u, 100u}) {
      for (std::uint32_t p = 0; p < paths.size(); p += 3) {
        for (std::uint32_t t = 2; t <= paths[p].size(); ++t) {
          const StreamId camera_id{.key = 9, .purpose = StreamPurpose::kCameraPath, .path = p};
          const StreamId draws_id{.key = 9, .purpose = StreamPurpose::kResampling, .path = p};
          RandomStream camera_a(camera_id), draws_a(draws_id), camera_b(camera_id),
              draws_b(draws_id);
          TraceCounters counters_a, counters_b;
          const std::span<const PathVertex> vertices = std::span(paths[p]).first(t);
          CameraPrefix a{.pixel = p,
                         .vertices = vertices,
                         .max_s = 1,
                         .camera = camera_a,
                         .draws = draws_a,
                         .counters = counters_a};
          CameraPrefix b{.pixel = p,
                         .vertices = vertices,
                         .max_s = 1,
                         .camera = camera_b,
                         .draws = draws_b,
                         .counters = counters_b};
          const EmitterSample got = resample_emitters(services, a, candidates, target);
          const EmitterSample want = resample_one_by_one(services, b, candidates, target);
          const std::string where = "pixel " + std::to_string(p) + " t " + std::to_string(t) +
                                    " M " + std::to_string(candidates);
          ASSERT_EQ(
              std::memcmp(&got.contribution_weight, &want.contribution_weight, sizeof(double)), 0)
              << where;
          ASSERT_TRUE(same_bits(got.at_owner.value, want.at_owner.value)) << where;
          ASSERT_EQ(got.at_owner.density, want.at_owner.density) << where;
          ASSERT_EQ(std::memcmp(&got.point.position, &want.point.position, sizeof(Vec3)), 0)
              << where;
          ASSERT_TRUE(same_bits(got.point.beta, want.point.beta)) << where;
          ASSERT_EQ(got.point.triangle, want.point.triangle) << where;
          ASSERT_TRUE(same_counters(counters_a, counters_b)) << where;
          // Both streams are left where the one-by-one code leaves them.
          ASSERT_EQ(camera_a.uniform(), camera_b.uniform()) << where;
          ASSERT_EQ(draws_a.uniform(), draws_b.uniform()) << where;
          if (!want.empty()) ++kept_some;
        }
      }
    }
  }
  EXPECT_GT(kept_some, 50u);
}

// restir's targets a prefix at a time: emitter_targets of a batch gives each point's
// emitter_target, value bits, density and counters (shadow rays included for the visible
// target), for batches of 1 to 33 points (the pixel and up to 32 neighbours).
TEST_P(NextEventValuesOn, TargetsOfABatchAreTheTargetsOneByOne) {
  const Scene scene = built_in(GetParam());
  const auto paths = camera_paths(scene);
  const StrategyCounts counts{.next_event = 16.0};
  const RenderServices services(scene, counts, 0x7e57, 1, nullptr);
  RandomStream rng({.key = 12, .purpose = StreamPurpose::kCameraPath});
  std::size_t compared = 0;
  for (const EmitterTarget target : {EmitterTarget::kUnshadowed, EmitterTarget::kVisible}) {
    for (std::uint32_t p = 0; p < paths.size(); p += 5) {
      for (std::uint32_t t = 2; t <= paths[p].size(); ++t) {
        const std::span<const PathVertex> camera = std::span(paths[p]).first(t);
        const std::size_t n = 1 + (p + t) % 33;
        std::vector<PathVertex> points;
        for (std::size_t j = 0; j < n; ++j) points.push_back(sample_emitter_vertex(scene, rng));
        std::vector<const PathVertex*> xs;
        for (const PathVertex& x : points) xs.push_back(&x);
        std::vector<EmitterTargetValue> batch(n);
        TraceCounters together, alone;
        emitter_targets(services, xs, camera, target, batch, together);
        for (std::size_t j = 0; j < n; ++j) {
          const EmitterTargetValue one = emitter_target(services, points[j], camera, target, alone);
          ASSERT_TRUE(same_bits(batch[j].value, one.value)) << "pixel " << p << " t " << t;
          ASSERT_EQ(batch[j].density, one.density) << "pixel " << p << " t " << t;
          ++compared;
        }
        ASSERT_TRUE(same_counters(together, alone)) << "pixel " << p << " t " << t;
      }
    }
  }
  EXPECT_GT(compared, 500u);
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, NextEventValuesOn,
                         ::testing::Values("furnace", "cornell", "cornell-glossy", "door-ajar",
                                           "lampshade", "many-lights"),
                         scene_test_name);

}  // namespace
}  // namespace pcbench::scene
