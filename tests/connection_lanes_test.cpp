// A row's connections many at a time (integrands/scenes/connection_lanes.h): next events
// against connect() and mis_weight() one at a time, on every built-in scene: the same values,
// weights and counters to the bit, under path tracing's counts and others with no strategy but
// emitter hits and next events; any other connection's value against connect()'s; the queue's
// emitter samples (ConnectionQueue::connect_emitter_sample) against vertices sampled beforehand;
// and a prefix's subtotal. The images these make are checked whole by ctest estimators.hashes.
#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/rng.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/connection.h"
#include "integrands/scenes/connection_lanes.h"
#include "integrands/scenes/connection_queue.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/render_services.h"
#include "integrands/scenes/scene.h"
#include "test_support.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kResolution = 12;

class ConnectionLanesOn : public ::testing::TestWithParam<std::string> {};

// Prefix y_0 .. y_{t-1} of pixel p's path with room for one light vertex, both streams `rng`.
CameraPrefix next_event_prefix(const std::vector<std::vector<PathVertex>>& paths, std::uint32_t p,
                               std::uint32_t t, RandomStream& rng, TraceCounters& counters) {
  return {.pixel = p,
          .vertices = std::span(paths[p]).first(t),
          .max_s = 1,
          .camera = rng,
          .draws = rng,
          .counters = counters};
}

Scene small_scene(const std::string& name) {
  SceneDescription d = *built_in_scene(name);
  d.width = d.height = kResolution;
  return Scene(std::move(d));
}

// A camera subpath through every pixel, from streams of `key`.
std::vector<std::vector<PathVertex>> camera_paths(const Scene& scene, std::uint64_t key) {
  std::vector<std::vector<PathVertex>> paths(kResolution * kResolution);
  TraceCounters setup;
  for (std::uint32_t p = 0; p < paths.size(); ++p) {
    RandomStream rng({.key = key, .purpose = StreamPurpose::kCameraPath, .path = p});
    const double fx = p % kResolution + rng.uniform(), fy = p / kResolution + rng.uniform();
    trace_camera_path(scene, fx, fy, rng, scene.description().max_length, paths[p], setup);
  }
  return paths;
}

TEST_P(ConnectionLanesOn, ValuesWeightsAndCountersAreConnectsAndMisWeights) {
  const Scene scene = small_scene(GetParam());
  const auto paths = camera_paths(scene, 0x7e58);
  // Every prefix with t >= 2, twice, each with an emitter vertex of its own.
  std::vector<PathVertex> emitters;
  emitters.reserve(2 * paths.size() * (scene.description().max_length + 1));
  std::vector<ConnectionPair> pairs;
  RandomStream rng({.key = 0x7e58, .purpose = StreamPurpose::kEstimatorAux});
  for (int round = 0; round < 2; ++round) {
    for (const auto& path : paths) {
      for (std::uint32_t t = 2; t <= path.size(); ++t) {
        emitters.push_back(sample_emitter_vertex(scene, rng));
        pairs.push_back({std::span(&emitters.back(), 1), std::span(path).first(t)});
      }
    }
  }
  ASSERT_TRUE(all_next_events(pairs));
  std::size_t weighed = 0;
  for (const StrategyCounts counts :
       {StrategyCounts{.emitter_hit = 1.0, .next_event = 1.0, .connection = 0.0},
        StrategyCounts{.emitter_hit = 1.0, .next_event = 4.0, .connection = 0.0},
        StrategyCounts{.emitter_hit = 0.5, .next_event = 2.0, .connection = 0.0},
        StrategyCounts{.emitter_hit = 1.0, .next_event = 0.0, .connection = 0.0}}) {
    ASSERT_TRUE(next_event_only(counts));
    std::vector<Rgb> values(pairs.size());
    std::vector<double> weights(pairs.size());
    TraceCounters batch, reference;
    next_event_values_and_weights(scene, counts, pairs, values, weights, batch);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const Rgb want = connect(scene, pairs[i].light, pairs[i].camera, counts,
                               {.visibility = false, .weighted = false}, reference);
      ASSERT_TRUE(bit_identical(values[i].r, want.r) && bit_identical(values[i].g, want.g) &&
                  bit_identical(values[i].b, want.b))
          << "pair " << i << " t " << pairs[i].camera.size();
      if (want.is_black()) continue;
      const double w = mis_weight(scene, pairs[i].light, pairs[i].camera, counts);
      ASSERT_TRUE(bit_identical(weights[i], w)) << "pair " << i << ": " << weights[i] << " " << w;
      ++weighed;
    }
    EXPECT_EQ(batch.connections, reference.connections);
    EXPECT_EQ(batch.skipped_zero, reference.skipped_zero);
  }
  EXPECT_GT(weighed, 100u);  // the comparison saw weights, not only zeros
}

// A light subpath from every pixel's stream of `key`.
std::vector<std::vector<PathVertex>> light_paths(const Scene& scene, std::uint64_t key) {
  std::vector<std::vector<PathVertex>> paths(kResolution * kResolution);
  TraceCounters setup;
  for (std::uint32_t p = 0; p < paths.size(); ++p) {
    RandomStream rng({.key = key, .purpose = StreamPurpose::kLightPool, .path = p});
    trace_light_path(scene, rng, scene.description().max_length, paths[p], setup);
  }
  return paths;
}

// connection_values, the values of every strategy with s >= 1 and t >= 2 in lanes (BDPT's
// connections, the light vertex cache's and pcbpt's draws), against connect() one at a time:
// emitter and surface light ends, Lambertian, Phong and mirror (delta) ends on the scenes that
// have them, and counts that switch strategies off; the same values and counters to the bit.
TEST_P(ConnectionLanesOn, ConnectionValuesAreConnects) {
  const Scene scene = small_scene(GetParam());
  const auto cameras = camera_paths(scene, 0xc0e1);
  const auto lights = light_paths(scene, 0xc0e1);
  std::vector<ConnectionPair> pairs;
  std::size_t surface_light_ends = 0;
  for (std::uint32_t p = 0; p < cameras.size(); ++p) {
    const auto& light = lights[(p * 7) % lights.size()];  // not the pixel's own: more variety
    for (std::uint32_t s = 1; s <= light.size(); ++s) {
      for (std::uint32_t t = 2; t <= cameras[p].size(); ++t) {
        pairs.push_back({std::span(light).first(s), std::span(cameras[p]).first(t)});
        surface_light_ends += s >= 2 ? 1 : 0;
      }
    }
  }
  ASSERT_TRUE(all_camera_surface_ends(pairs));
  ASSERT_GT(surface_light_ends, 100u);
  std::size_t nonzero = 0;
  for (const StrategyCounts counts :
       {StrategyCounts{}, StrategyCounts{.next_event = 0.0},
        StrategyCounts{.emitter_hit = 1.0, .next_event = 8.0, .connection = 8.0},
        StrategyCounts{.connection = 0.0}}) {
    std::vector<Rgb> values(pairs.size());
    TraceCounters batch, reference;
    connection_values(scene, counts, pairs, values, batch);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const Rgb want = connect(scene, pairs[i].light, pairs[i].camera, counts,
                               {.visibility = false, .weighted = false}, reference);
      ASSERT_TRUE(bit_identical(values[i].r, want.r) && bit_identical(values[i].g, want.g) &&
                  bit_identical(values[i].b, want.b))
          << "pair " << i << " s " << pairs[i].light.size() << " t " << pairs[i].camera.size()
          << ": " << values[i].r << " " << want.r;
      if (!want.is_black()) ++nonzero;
    }
    EXPECT_EQ(batch.connections, reference.connections);
    EXPECT_EQ(batch.skipped_zero, reference.skipped_zero);
  }
  EXPECT_GT(nonzero, 100u);  // the comparison saw values, not only zeros
}

// connection_weights, the weights of a batch's unblocked connections with s >= 1 and t >= 2
// (in lanes where the subpaths' sums are stored and the ends are Lambertian or an emitter),
// against mis_weight() one at a time: every connection whose value is not 0, with the sums
// stored for the counts (the renderer's case) and never stored (the weights then loop, as they do
// under a count model), emitter and surface light ends, Phong and mirror vertices on the scenes
// that have them; the same weights to the bit.
TEST_P(ConnectionLanesOn, ConnectionWeightsAreMisWeights) {
  const Scene scene = small_scene(GetParam());
  std::size_t in_lanes = 0, weighed = 0;
  for (const StrategyCounts counts :
       {StrategyCounts{}, StrategyCounts{.light_tracing = 144.0},
        StrategyCounts{.emitter_hit = 1.0, .next_event = 8.0, .connection = 8.0},
        StrategyCounts{.next_event = 0.0}}) {
    for (const bool stored : {true, false}) {
      auto cameras = camera_paths(scene, 0xc0e2);
      auto lights = light_paths(scene, 0xc0e2);
      if (stored) {
        for (auto& path : cameras) store_camera_weight_sums(path, counts);
        for (auto& path : lights) store_light_weight_sums(path, counts);
      }
      std::vector<ConnectionPair> pairs;
      std::vector<std::uint32_t> which;  // the pairs whose value is not 0
      TraceCounters counters;
      for (std::uint32_t p = 0; p < cameras.size(); ++p) {
        const auto& light = lights[(p * 5) % lights.size()];
        for (std::uint32_t s = 1; s <= light.size(); ++s) {
          for (std::uint32_t t = 2; t <= cameras[p].size(); ++t) {
            const ConnectionPair pair{std::span(light).first(s), std::span(cameras[p]).first(t)};
            const Rgb value = connect(scene, pair.light, pair.camera, counts,
                                      {.visibility = false, .weighted = false}, counters);
            if (value.is_black()) continue;
            which.push_back(static_cast<std::uint32_t>(pairs.size()));
            pairs.push_back(pair);
            in_lanes += weight_sums_stored(pair.light, pair.camera, counts) ? 1 : 0;
          }
        }
      }
      std::vector<double> weights(which.size());
      connection_weights(scene, counts, pairs, which, weights);
      for (std::size_t k = 0; k < which.size(); ++k) {
        const ConnectionPair& pair = pairs[which[k]];
        const double want = mis_weight(scene, pair.light, pair.camera, counts);
        ASSERT_TRUE(bit_identical(weights[k], want))
            << "pair " << which[k] << " s " << pair.light.size() << " t " << pair.camera.size()
            << (stored ? ", sums stored: " : ": ") << weights[k] << " " << want;
      }
      weighed += which.size();
    }
  }
  EXPECT_GT(weighed, 200u);  // the comparison saw weights, most from stored sums
  EXPECT_GT(in_lanes, 100u);
}

// light_tracing_values, light tracing's values in lanes (every pool path's splats: BDPT's, lt's,
// pcbpt's), against connect() with its pixel, one at a time: every prefix of a light subpath
// from each pixel's stream joined to the camera, under counts with light tracing and without;
// the same values, pixels and counters to the bit.
TEST_P(ConnectionLanesOn, LightTracingValuesAreConnects) {
  const Scene scene = small_scene(GetParam());
  const auto lights = light_paths(scene, 0x1e75);
  const PathVertex camera = camera_paths(scene, 0x1e75)[0][0];  // y_0, the camera's vertex
  std::vector<ConnectionPair> pairs;
  for (const auto& light : lights) {
    for (std::uint32_t s = 1; s <= light.size(); ++s) {
      pairs.push_back({std::span(light).first(s), std::span(&camera, 1)});
    }
  }
  ASSERT_TRUE(all_light_tracing(pairs));
  std::size_t landed = 0, nonzero = 0;
  for (const StrategyCounts counts :
       {StrategyCounts{.light_tracing = 144.0}, StrategyCounts{.light_tracing = 0.0}}) {
    std::vector<Rgb> values(pairs.size());
    std::vector<std::optional<PixelPosition>> pixels(pairs.size());
    TraceCounters batch, reference;
    light_tracing_values(scene, counts, pairs, values, pixels, batch);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      std::optional<PixelPosition> want_pixel;
      const Rgb want = connect(scene, pairs[i].light, pairs[i].camera, counts,
                               {.visibility = false, .weighted = false}, reference, &want_pixel);
      ASSERT_TRUE(bit_identical(values[i].r, want.r) && bit_identical(values[i].g, want.g) &&
                  bit_identical(values[i].b, want.b))
          << "pair " << i << " s " << pairs[i].light.size() << ": " << values[i].r << " " << want.r;
      ASSERT_EQ(pixels[i].has_value(), want_pixel.has_value()) << "pair " << i;
      if (want_pixel) {
        ASSERT_EQ(pixels[i]->x, want_pixel->x);
        ASSERT_EQ(pixels[i]->y, want_pixel->y);
        ASSERT_TRUE(bit_identical(pixels[i]->cos_theta, want_pixel->cos_theta));
        ++landed;
      }
      if (!want.is_black()) ++nonzero;
    }
    EXPECT_EQ(batch.connections, reference.connections);
    EXPECT_EQ(batch.skipped_zero, reference.skipped_zero);
  }
  EXPECT_GT(landed, 50u);  // the comparison saw pixels and values, not only misses
  EXPECT_GT(nonzero, 50u);
}

// A row's requests through ConnectionQueue: emitter vertices the queue samples itself
// (connect_emitter_sample, the points drawn in lanes when every request is one and the counts
// have nothing else) against vertices sampled beforehand (connect), with the same streams:
// the same values and counters to the bit, also mixed with other requests and under counts
// with connections (where the sampled vertices are made one by one).
TEST_P(ConnectionLanesOn, QueuedEmitterSamplesAreSampledVertices) {
  const Scene scene = small_scene(GetParam());
  const auto paths = camera_paths(scene, 0x7e59);
  std::size_t nonzero = 0, unoccluded_nonzero = 0;  // before and after the shadow rays
  for (const StrategyCounts counts :
       {StrategyCounts{.emitter_hit = 1.0, .next_event = 1.0, .connection = 0.0},
        StrategyCounts{.emitter_hit = 1.0, .next_event = 2.0, .connection = 0.0},
        StrategyCounts{}}) {
    for (const bool mixed : {false, true}) {
      ConnectionQueue sampled, made;
      TraceCounters sampled_counters, made_counters;
      const StreamId id{.key = 0x7e59, .purpose = StreamPurpose::kEstimatorAux};
      RandomStream rng_a(id), rng_b(id);
      sampled.clear();
      made.clear();
      for (std::uint32_t p = 0; p < paths.size(); ++p) {
        for (std::uint32_t t = 2; t <= paths[p].size(); ++t) {
          const CameraPrefix a = next_event_prefix(paths, p, t, rng_a, sampled_counters);
          const CameraPrefix b = next_event_prefix(paths, p, t, rng_b, made_counters);
          sampled.begin_prefix(a, false, {});
          made.begin_prefix(b, false, {});
          sampled.connect_emitter_sample(rng_a, a, 0.5);
          made.connect(sample_emitter_vertex(scene, rng_b), b, 0.5);
          if (mixed && t % 2 == 0) {  // a vertex sampled by the pass among them
            sampled.connect(sample_emitter_vertex(scene, rng_a), a);
            made.connect(sample_emitter_vertex(scene, rng_b), b);
          }
        }
      }
      sampled.resolve(scene, counts, sampled_counters);
      made.resolve(scene, counts, made_counters);
      for (const auto& prefix : made.prefixes()) {
        for (std::uint32_t i = prefix.first; i < prefix.end; ++i) {
          const Rgb& got = sampled.value(i);
          const Rgb& want = made.value(i);
          ASSERT_TRUE(bit_identical(got.r, want.r) && bit_identical(got.g, want.g) &&
                      bit_identical(got.b, want.b))
              << "request " << i << (mixed ? ", mixed" : "");
          ASSERT_EQ(sampled.strategy(i), made.strategy(i));
          if (!want.is_black()) ++nonzero;
        }
      }
      unoccluded_nonzero += made_counters.shadow_rays + made_counters.skipped_convex;
      EXPECT_EQ(sampled_counters.connections, made_counters.connections);
      EXPECT_EQ(sampled_counters.skipped_zero, made_counters.skipped_zero);
      EXPECT_EQ(sampled_counters.shadow_rays, made_counters.shadow_rays);
      EXPECT_EQ(sampled_counters.occluded, made_counters.occluded);
      EXPECT_EQ(sampled_counters.skipped_convex, made_counters.skipped_convex);
    }
  }
  // The comparison saw values that reached their shadow rays (door-ajar's are nearly all blocked
  // at this resolution), and on every scene but door-ajar unblocked ones.
  EXPECT_GT(unoccluded_nonzero, 100u);
  if (GetParam() != "door-ajar") {
    EXPECT_GT(nonzero, 100u);
  }
}

// A prefix's subtotal (ConnectionQueue::begin_subtotal, pcbpt's next event then its draws):
// the prefix adds a + (b + c), not (a + b) + c, and each request's own value is unchanged; a
// second subtotal for one prefix is an error.
TEST(ConnectionQueueSum, SubtotalAddsItsGroupFirst) {
  const Scene scene = small_scene("cornell");
  const auto paths = camera_paths(scene, 0x5ab7);
  ConnectionQueue queue;
  TraceCounters counters;
  RandomStream rng({.key = 0x5ab7, .purpose = StreamPurpose::kEstimatorAux});
  for (std::uint32_t p = 0; p < paths.size(); ++p) {
    for (std::uint32_t t = 2; t <= paths[p].size(); ++t) {
      const CameraPrefix prefix = next_event_prefix(paths, p, t, rng, counters);
      queue.begin_prefix(prefix, false, {});
      queue.connect_emitter_sample(rng, prefix, 0.3);
      queue.begin_subtotal(prefix);
      EXPECT_THROW(queue.begin_subtotal(prefix), std::logic_error);
      queue.connect_emitter_sample(rng, prefix, 0.7);
      queue.connect_emitter_sample(rng, prefix, 1.1);
    }
  }
  queue.resolve(scene, StrategyCounts{.connection = 0.0}, counters);
  std::size_t order_matters = 0;  // prefixes where (a + b) + c would differ
  for (const auto& prefix : queue.prefixes()) {
    ASSERT_EQ(prefix.end - prefix.first, 3u);
    const Rgb& a = queue.value(prefix.first);
    const Rgb& b = queue.value(prefix.first + 1);
    const Rgb& c = queue.value(prefix.first + 2);
    const Rgb want = a + (b + c), left_first = (a + b) + c;
    const Rgb got = queue.sum(prefix);
    ASSERT_TRUE(bit_identical(got.r, want.r) && bit_identical(got.g, want.g) &&
                bit_identical(got.b, want.b));
    if (!bit_identical(left_first.r, want.r) || !bit_identical(left_first.g, want.g) ||
        !bit_identical(left_first.b, want.b)) {
      ++order_matters;
    }
  }
  EXPECT_GT(order_matters, 10u);  // the comparison could fail
}

TEST(ConnectionLanes, TakesThePairsAndCountsItComputes) {
  EXPECT_TRUE(next_event_only({.emitter_hit = 1.0, .next_event = 1.0, .connection = 0.0}));
  EXPECT_FALSE(next_event_only({}));  // BDPT's: connections
  EXPECT_FALSE(next_event_only({.connection = 0.0, .light_tracing = 16384.0}));
  std::vector<PathVertex> camera(3), light(2);
  light[0].kind = VertexKind::kEmitter;
  EXPECT_TRUE(
      all_next_events(std::vector<ConnectionPair>{{std::span(light).first(1), std::span(camera)}}));
  EXPECT_FALSE(all_next_events(
      std::vector<ConnectionPair>{{std::span(light), std::span(camera)}}));  // s = 2
  EXPECT_FALSE(all_next_events(std::vector<ConnectionPair>{
      {std::span(light).first(1), std::span(camera).first(1)}}));  // t = 1
  light[0].kind = VertexKind::kSurface;
  EXPECT_FALSE(
      all_next_events(std::vector<ConnectionPair>{{std::span(light).first(1), std::span(camera)}}));
  // connection_values takes any s >= 1 with t >= 2.
  EXPECT_TRUE(
      all_camera_surface_ends(std::vector<ConnectionPair>{{std::span(light), std::span(camera)}}));
  EXPECT_FALSE(all_camera_surface_ends(std::vector<ConnectionPair>{
      {std::span(light), std::span(camera).first(1)}}));  // t = 1: the lens
  EXPECT_FALSE(all_camera_surface_ends(std::vector<ConnectionPair>{
      {std::span(light).first(0), std::span(camera)}}));  // s = 0: an emitter hit
  // light_tracing_values takes s >= 1 with t = 1.
  EXPECT_TRUE(all_light_tracing(
      std::vector<ConnectionPair>{{std::span(light), std::span(camera).first(1)}}));
  EXPECT_FALSE(
      all_light_tracing(std::vector<ConnectionPair>{{std::span(light), std::span(camera)}}));
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, ConnectionLanesOn, ::testing::ValuesIn(built_in_scene_names()),
                         scene_test_name);

}  // namespace
}  // namespace pcbench::scene
