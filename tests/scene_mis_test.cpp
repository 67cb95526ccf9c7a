// The multiple-importance-sampling weights and connections of the scene code, on full paths
// z_0 .. z_k (z_0 at the camera, z_k on an emitter) taken from real subpaths:
//   - mis_weight gives strategy (s, t), s + t = k + 1, the balance heuristic n_s p_s / Σ n p
//     over the strategies of each scene estimator's StrategyCounts (every estimator of the
//     registry and of the examples that renders scenes, at its defaults and at the parameters its
//     entry's SceneTests declare; p: the product of the vertices' area densities as that
//     strategy samples them), so the weights sum to 1, whether it loops over the subpaths or
//     takes the sums their walks stored (store_camera_weight_sums, store_light_weight_sums);
//   - connect()'s unweighted value is the path's contribution f(z) divided by p_s;
//   - the walks' bookkeeping (pdf_fwd, pdf_rev, beta) matches the path.
// The densities and contributions here are computed from the vertex positions, apart from
// path_vertex.cpp and connection.cpp. Last, every honest estimator renders the built-in furnace
// to its exact radiance in each configuration its entry declares (SceneRenderFurnace), and the
// image does not depend on the thread count; and ctl-scene-nee-count's mistake is exactly the
// one it declares (SceneRenderControl). The estimators come from the registry, not from a list
// here (a new one is tested by its registry line); one is named only where a test needs its
// counts (pcbpt's, plain's) or checks one control's mistake (ctl-scene-nee-count against pt).
//
// Error budget: only SceneRenderFurnace is statistical: N configurations (19 today: 7 estimators
// and 12 pcbpt ablations) × 3 channels t tests, each asserting p > 1e-4, so a correct renderer
// fails by chance with probability at most 3N × 1e-4 = 5.7e-3 (Bonferroni); the test asserts
// 3N × 1e-4 <= 1%. The seeds are fixed.

#include <gtest/gtest.h>

#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "base/rng.h"
#include "estimators/registry.h"
#include "estimators/scene/render_replicate.h"
#include "examples/examples.h"
#include "harness/verify/statistics.h"
#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/connection.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {
namespace {

// ---------------------------------------------------------------------------------------------
// Full paths and their densities, from positions

// z[0] at the camera, z[1 .. k-1] on surfaces, z[k] on the front of an emitting triangle or at a
// point light. The vertices keep what the walk that made them recorded (pdf_fwd, pdf_rev, beta).
struct FullPath {
  std::vector<PathVertex> z;
  bool point_light = false;
  bool from_camera = true;  // a camera subpath's prefix; otherwise a light subpath reversed
  std::size_t k() const { return z.size() - 1; }
};

Vec3 unit(const Vec3& from, const Vec3& to) {
  return normalize(to - from);
}

// |cos| at vertex i of the direction w: 1 at the camera and at a point light.
double abs_cos(const FullPath& p, std::size_t i, const Vec3& w) {
  if (i == 0 || (i == p.k() && p.point_light)) return 1.0;
  return std::abs(dot(p.z[i].normal, w));
}

double geometry(const FullPath& p, std::size_t a, std::size_t b) {
  const Vec3 d = p.z[b].position - p.z[a].position;
  const Vec3 w = normalize(d);
  return abs_cos(p, a, w) * abs_cos(p, b, w) / dot(d, d);
}

double camera_cos(const Scene& scene, const Vec3& w) {
  const Camera& c = scene.description().camera;
  return dot(w, normalize(c.look_at - c.position));
}

// f at surface vertex i between its neighbours `from` and `to` (path indices).
Rgb scattering(const Scene& scene, const FullPath& p, std::size_t i, std::size_t from,
               std::size_t to) {
  const PathVertex& v = p.z[i];
  return bsdf_eval(scene.material(v.triangle), v.normal, unit(v.position, p.z[from].position),
                   unit(v.position, p.z[to].position));
}

Rgb emission(const Scene& scene, const FullPath& p) {
  const PathVertex& e = p.z[p.k()];
  if (p.point_light) return scene.description().point_lights[e.triangle].intensity;
  const bool front = dot(e.normal, p.z[p.k() - 1].position - e.position) > 0.0;
  return front ? scene.triangle(e.triangle).emission : Rgb{};
}

// Probability of choosing the path's emitter, by power, over the area of a triangle.
double emitter_density(const Scene& scene, const FullPath& p) {
  const SceneDescription& d = scene.description();
  double total = 0.0;
  for (const Triangle& t : d.triangles) total += kPi * triangle_area(t) * t.emission.average();
  for (const PointLight& l : d.point_lights) total += 4.0 * kPi * l.intensity.average();
  const std::uint32_t index = p.z[p.k()].triangle;
  if (p.point_light) return 4.0 * kPi * d.point_lights[index].intensity.average() / total;
  return kPi * d.triangles[index].emission.average() / total;  // (π A L / total) / A
}

// Area density at vertex `to` of sampling it from vertex `at`, which was reached from `from`
// (from < 0: `at` starts its subpath, at the camera or the emitter).
double area_density(const Scene& scene, const FullPath& p, std::size_t at, int from,
                    std::size_t to) {
  const PathVertex& v = p.z[at];
  const Vec3 w = unit(v.position, p.z[to].position);
  double solid_angle = 0.0;
  if (from < 0 && at == 0) {
    solid_angle = scene.camera().pixel_pdf(camera_cos(scene, w));
  } else if (from < 0 && p.point_light) {
    solid_angle = 1.0 / (4.0 * kPi);
  } else if (from < 0) {
    solid_angle = std::max(0.0, dot(v.normal, w)) / kPi;
  } else {
    solid_angle = bsdf_pdf(scene.material(v.triangle), v.normal,
                           unit(v.position, p.z[static_cast<std::size_t>(from)].position), w);
  }
  const Vec3 d = p.z[to].position - v.position;
  return solid_angle * abs_cos(p, to, w) / dot(d, d);
}

// Everything about one path that the strategies' densities and values are made of.
struct PathFacts {
  std::vector<double> camera_pdf;  // [i]: z_i sampled from z_{i-1} walking from the camera
  std::vector<double> light_pdf;   // [i]: z_i sampled walking from the emitter; [k]: the emitter
  std::vector<Rgb> camera_beta;    // throughput of the camera prefix z_0 .. z_i
  std::vector<Rgb> light_beta;     // throughput of the light prefix z_k .. z_i
  Rgb contribution;                // f(z): emission, BSDFs, geometry, camera importance
};

PathFacts facts(const Scene& scene, const FullPath& p) {
  const std::size_t k = p.k();
  PathFacts f;
  f.camera_pdf.assign(k + 1, 0.0);
  f.light_pdf.assign(k + 1, 0.0);
  for (std::size_t i = 1; i <= k; ++i) {
    f.camera_pdf[i] = area_density(scene, p, i - 1, static_cast<int>(i) - 2, i);
  }
  f.light_pdf[k] = emitter_density(scene, p);
  for (std::size_t i = k; i-- > 0;) {
    f.light_pdf[i] = area_density(scene, p, i + 1, i + 1 == k ? -1 : static_cast<int>(i) + 2, i);
  }
  // W_j cos at the camera is pixel_pdf (camera_model.h).
  const double camera_term =
      scene.camera().pixel_pdf(camera_cos(scene, unit(p.z[0].position, p.z[1].position)));
  f.camera_beta.assign(k + 1, Rgb{});
  f.camera_beta[0] = {1.0, 1.0, 1.0};
  f.camera_beta[1] = Rgb{1.0, 1.0, 1.0} * (camera_term * geometry(p, 0, 1) / f.camera_pdf[1]);
  for (std::size_t i = 2; i <= k; ++i) {
    f.camera_beta[i] = f.camera_beta[i - 1] * scattering(scene, p, i - 1, i - 2, i) *
                       (geometry(p, i - 1, i) / f.camera_pdf[i]);
  }
  f.light_beta.assign(k + 1, Rgb{});
  f.light_beta[k] = Rgb{1.0, 1.0, 1.0} / f.light_pdf[k];
  f.light_beta[k - 1] =
      f.light_beta[k] * emission(scene, p) * (geometry(p, k, k - 1) / f.light_pdf[k - 1]);
  for (std::size_t i = k - 1; i-- > 0;) {
    f.light_beta[i] = f.light_beta[i + 1] * scattering(scene, p, i + 1, i + 2, i) *
                      (geometry(p, i + 1, i) / f.light_pdf[i]);
  }
  f.contribution = emission(scene, p) * camera_term;
  for (std::size_t i = 1; i < k; ++i) {
    f.contribution = f.contribution * scattering(scene, p, i, i - 1, i + 1);
  }
  for (std::size_t i = 0; i < k; ++i) f.contribution = f.contribution * geometry(p, i, i + 1);
  return f;
}

// Density of strategy s: the light subpath makes z_k .. z_t, the camera subpath z_0 .. z_{t-1}.
double strategy_pdf(const PathFacts& f, std::size_t s) {
  const std::size_t k = f.camera_pdf.size() - 1, t = k + 1 - s;
  double pdf = 1.0;
  for (std::size_t i = t; i <= k; ++i) pdf *= f.light_pdf[i];
  for (std::size_t i = 1; i < t; ++i) pdf *= f.camera_pdf[i];
  return pdf;
}

// The subpaths of strategy s, with every density, direction and throughput as its own walks
// would have recorded them. The reverse densities of each subpath's last two vertices depend on
// where that walk went next, which the connection replaces: mis_weight must compute them
// itself, so they are NaN here (and any use of them shows in the result).
constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

struct Split {
  std::vector<PathVertex> light, camera;
};

Split split(const Scene& scene, const FullPath& p, const PathFacts& f, std::size_t s) {
  const std::size_t k = p.k(), t = k + 1 - s;
  Split out;
  for (std::size_t i = 0; i < t; ++i) {
    PathVertex v;
    v.kind = i == 0 ? VertexKind::kCamera : VertexKind::kSurface;
    v.position = p.z[i].position;
    if (i > 0) {
      v.normal = p.z[i].normal;
      v.triangle = p.z[i].triangle;
      v.to_previous = unit(v.position, p.z[i - 1].position);
      v.delta = is_delta(scene.material(v.triangle));
    }
    v.beta = f.camera_beta[i];
    v.pdf_fwd = i == 0 ? 0.0 : f.camera_pdf[i];
    v.pdf_rev = i + 2 >= t ? kUnknown : f.light_pdf[i];
    out.camera.push_back(v);
  }
  for (std::size_t j = 0; j < s; ++j) {
    const std::size_t i = k - j;
    PathVertex v;
    v.kind = j == 0 ? VertexKind::kEmitter : VertexKind::kSurface;
    v.point_light = j == 0 && p.point_light;
    v.position = p.z[i].position;
    v.triangle = p.z[i].triangle;
    if (!v.point_light) v.normal = p.z[i].normal;
    if (j > 0) {
      v.to_previous = unit(v.position, p.z[i + 1].position);
      v.delta = is_delta(scene.material(v.triangle));
    }
    v.beta = f.light_beta[i];
    v.pdf_fwd = f.light_pdf[i];
    v.pdf_rev = j + 2 >= s ? kUnknown : f.camera_pdf[i];
    out.light.push_back(v);
  }
  return out;
}

// Whether strategy s can make this path at all (no camera subpath hits a point light).
bool possible(const FullPath& p, std::size_t s) {
  return !(s == 0 && p.point_light);
}

// ---------------------------------------------------------------------------------------------
// Where the paths come from

// Prefixes of camera subpaths that end on the front of an emitting triangle.
std::vector<FullPath> camera_paths(const Scene& scene, std::size_t wanted, std::uint64_t key) {
  const SceneDescription& d = scene.description();
  std::vector<FullPath> out;
  std::vector<PathVertex> path;
  TraceCounters counters;
  for (std::uint32_t n = 0; out.size() < wanted && n < 1000000; ++n) {
    RandomStream rng({.key = key, .path = n});
    const double fx = rng.uniform() * d.width, fy = rng.uniform() * d.height;
    trace_camera_path(scene, fx, fy, rng, d.max_length, path, counters);
    for (std::size_t k = 1; k < path.size() && out.size() < wanted; ++k) {
      const PathVertex& v = path[k];
      if (scene.triangle(v.triangle).emission.is_black()) continue;
      if (dot(v.normal, v.to_previous) <= 0.0) continue;
      out.push_back({std::vector<PathVertex>(path.begin(), path.begin() + k + 1), false, true});
    }
  }
  return out;
}

// Light subpath prefixes x_0 .. x_j that the camera sees, reversed (z_0 the camera).
std::vector<FullPath> light_paths(const Scene& scene, std::size_t wanted, std::uint64_t key) {
  const SceneDescription& d = scene.description();
  std::vector<FullPath> out;
  std::vector<PathVertex> path;
  TraceCounters counters;
  PathVertex camera;
  camera.kind = VertexKind::kCamera;
  camera.position = scene.camera().position();
  for (std::uint32_t n = 0; out.size() < wanted && n < 1000000; ++n) {
    RandomStream rng({.key = key, .path = n});
    trace_light_path(scene, rng, d.max_length, path, counters);
    for (std::size_t j = 0; j < path.size() && out.size() < wanted; ++j) {
      if (!scene.camera().project(unit(camera.position, path[j].position))) continue;
      if (scene.occluded(camera.position, path[j].position)) continue;
      FullPath p{{camera}, path[0].point_light, false};
      for (std::size_t i = j + 1; i-- > 0;) p.z.push_back(path[i]);
      out.push_back(std::move(p));
    }
  }
  return out;
}

// Paths the MIS weights are defined on: a non-zero contribution and densities.
bool usable(const PathFacts& f) {
  if (f.contribution.is_black()) return false;
  for (std::size_t i = 1; i < f.camera_pdf.size(); ++i) {
    if (!(f.camera_pdf[i] > 0.0) || !(f.light_pdf[i] > 0.0)) return false;
  }
  return true;
}

Scene scene_named(const std::string& name) {
  return Scene(*built_in_scene(name));
}

// Cornell with a point light under the area light too.
SceneDescription cornell_with_point_light() {
  SceneDescription d = *built_in_scene("cornell");
  d.point_lights.push_back({{0.5, 0.8, 0.6}, {0.6, 0.5, 0.4}});
  return d;
}

struct NamedEstimator {
  std::string name;
  std::shared_ptr<const SceneEstimator> estimator;
};

// Every scene estimator of the registry and of the examples (examples/examples.cpp, registered in
// pcbench_examples only), as its entry declares it: this file names none of them.
std::vector<const EstimatorEntry*> scene_entries() {
  static const std::vector<EstimatorEntry> examples = examples::example_entries();
  std::vector<const EstimatorEntry*> out;
  for (const auto* table : {&estimator_registry(), &scene_estimator_registry(), &examples}) {
    for (const EstimatorEntry& e : *table) {
      if (e.renders_scenes()) out.push_back(&e);
    }
  }
  return out;
}

NamedEstimator make(const EstimatorEntry& e, const NamedParams& config) {
  return {config.name.empty() ? e.name : e.name + " " + config.name,
          e.make_render(resolve_params(e.scene_params, config.params, e.name))};
}

// Every scene estimator at its defaults (pool sizes and draw counts of a typical run: they set
// StrategyCounts) and at the further parameters its entry declares (pcbpt's ablations).
std::vector<NamedEstimator> every_estimator() {
  std::vector<NamedEstimator> out;
  for (const EstimatorEntry* e : scene_entries()) {
    out.push_back(make(*e, {}));
    for (const NamedParams& config : e->scene_tests.weights) out.push_back(make(*e, config));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// MIS weights

// For each path and method: mis_weight of every included strategy (count > 0) is the balance
// heuristic over the included strategies, and they sum to 1; from the subpaths' stored sums
// (store_camera_weight_sums) too, for the methods whose counts need no model.
void check_weights(const Scene& scene, const std::vector<FullPath>& paths) {
  const std::vector<NamedEstimator> estimators = every_estimator();
  EXPECT_GE(estimators.size(), 10u);  // pt, lt, plain, vc-all, lvc, pcbpt, 3 controls, example
  std::size_t checked = 0, from_stored_sums = 0;
  for (std::size_t n = 0; n < paths.size(); ++n) {
    const FullPath& p = paths[n];
    const PathFacts f = facts(scene, p);
    if (!usable(f)) continue;
    const std::size_t k = p.k();
    for (const NamedEstimator& method : estimators) {
      SCOPED_TRACE("path " + std::to_string(n) + " k " + std::to_string(k) + " " + method.name);
      const StrategyCounts counts = method.estimator->strategy_counts(scene);
      double total = 0.0;
      for (std::size_t s = 0; s <= k; ++s) {
        const double c =
            counts.count(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(k + 1 - s));
        if (c > 0.0 && possible(p, s)) total += c * strategy_pdf(f, s);
      }
      if (total == 0.0) continue;  // no strategy of this method makes the path
      double sum = 0.0;
      for (std::size_t s = 0; s <= k; ++s) {
        const double c =
            counts.count(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(k + 1 - s));
        if (c <= 0.0 || !possible(p, s)) continue;  // weight 0: connect() skips it
        Split parts = split(scene, p, f, s);
        const double w = mis_weight(scene, parts.light, parts.camera, counts);
        EXPECT_NEAR(w, c * strategy_pdf(f, s) / total, 1e-9) << "s " << s;
        sum += w;
        // The same weight from the subpaths' stored sums, as the renderer's walks leave them.
        store_camera_weight_sums(parts.camera, counts);
        store_light_weight_sums(parts.light, counts);
        const double from_sums = mis_weight(scene, parts.light, parts.camera, counts);
        EXPECT_NEAR(from_sums, c * strategy_pdf(f, s) / total, 1e-9) << "s " << s << ", sums";
        from_stored_sums += parts.camera.size() >= 3 && !std::isnan(parts.camera[0].weight_sum);
      }
      EXPECT_NEAR(sum, 1.0, 1e-9);
      ++checked;
    }
  }
  EXPECT_GT(checked, paths.size());           // several methods per path
  EXPECT_GT(from_stored_sums, paths.size());  // the stored sums were used, not the loop
}

// A count model (connection.h) that depends on both things it is given, the light side's
// importance and the camera-side end's position, as pcbpt's mis=resampling does.
// With next_event false it leaves s = 1 at its constant count, as pcbpt's nee=fresh does.
class TestCountModel final : public ConnectionCountModel {
 public:
  explicit TestCountModel(bool next_event) : next_event_(next_event) {}
  double count(double importance, const Vec3& camera_end, double constant) const override {
    if (importance < 0.0) return constant;
    return constant * (0.1 + importance) * (1.0 + camera_end.y * camera_end.y);
  }
  bool counts_next_event() const override { return next_event_; }

 private:
  bool next_event_;
};

// q*_s of strategy s (light vertices z_k .. z_{k-s+1}, camera-side end z_{k-s}), from the
// positions: the light prefix's throughput × its last vertex's emission or BSDF towards z_{k-s}
// × G; -1 when a vertex of the light prefix after the emitter is specular.
double light_side_importance(const Scene& scene, const FullPath& p, const PathFacts& f,
                             std::size_t s) {
  const std::size_t k = p.k(), end = k - s + 1;
  for (std::size_t i = end; i < k; ++i) {
    if (is_delta(scene.material(p.z[i].triangle))) return -1.0;
  }
  const Rgb towards = end == k ? emission(scene, p) : scattering(scene, p, end, end + 1, end - 1);
  return (f.light_beta[end] * towards).max_channel() * geometry(p, end, end - 1);
}

// With path-dependent counts, each weight is still the balance heuristic over the counts the
// model gives every strategy of the path, and they sum to 1.
void check_weights_with_a_count_model(const Scene& scene, const std::vector<FullPath>& paths,
                                      bool next_event) {
  const TestCountModel model(next_event);
  StrategyCounts counts = make_scene_estimator("pcbpt")->strategy_counts(scene);
  counts.model = &model;
  std::size_t checked = 0, varied = 0;
  for (std::size_t n = 0; n < paths.size(); ++n) {
    const FullPath& p = paths[n];
    const PathFacts f = facts(scene, p);
    if (!usable(f)) continue;
    const std::size_t k = p.k();
    SCOPED_TRACE("path " + std::to_string(n) + " k " + std::to_string(k));
    std::vector<double> c(k + 1, 0.0);
    double total = 0.0;
    for (std::size_t s = 0; s <= k; ++s) {
      c[s] = counts.count(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(k + 1 - s));
      if (s >= 1 && k + 1 - s >= 2 && c[s] > 0.0 && (s >= 2 || next_event)) {
        const double changed =
            model.count(light_side_importance(scene, p, f, s), p.z[k - s].position, c[s]);
        varied += changed != c[s];
        c[s] = changed;
      }
      if (c[s] > 0.0 && possible(p, s)) total += c[s] * strategy_pdf(f, s);
    }
    if (total == 0.0) continue;
    double sum = 0.0;
    for (std::size_t s = 0; s <= k; ++s) {
      if (c[s] <= 0.0 || !possible(p, s)) continue;
      const Split parts = split(scene, p, f, s);
      const double w = mis_weight(scene, parts.light, parts.camera, counts);
      EXPECT_NEAR(w, c[s] * strategy_pdf(f, s) / total, 1e-9) << "s " << s;
      sum += w;
    }
    EXPECT_NEAR(sum, 1.0, 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, paths.size() / 2);
  EXPECT_GT(varied, checked);  // the model changed counts on most paths
}

TEST(SceneMisWeights, PathCountsSumToOne) {
  for (const bool next_event : {true, false}) {
    SCOPED_TRACE(next_event ? "next event counted by the model" : "next event constant");
    for (const std::string name : {"furnace", "cornell", "cornell-glossy"}) {
      SCOPED_TRACE(name);
      const Scene scene = scene_named(name);
      check_weights_with_a_count_model(scene, camera_paths(scene, 100, 500), next_event);
    }
    const Scene scene(cornell_with_point_light());
    check_weights_with_a_count_model(scene, light_paths(scene, 100, 600), next_event);
  }
}

TEST(SceneMisWeights, SumToOneInTheFurnace) {
  const Scene scene = scene_named("furnace");
  check_weights(scene, camera_paths(scene, 200, 100));
}

TEST(SceneMisWeights, SumToOneInCornell) {
  const Scene scene = scene_named("cornell");
  check_weights(scene, camera_paths(scene, 100, 200));
}

TEST(SceneMisWeights, SumToOneInCornellGlossy) {
  const Scene scene = scene_named("cornell-glossy");
  check_weights(scene, camera_paths(scene, 100, 300));
}

TEST(SceneMisWeights, SumToOneWithAPointLight) {
  const Scene scene(cornell_with_point_light());
  const std::vector<FullPath> paths = light_paths(scene, 200, 400);
  std::size_t point = 0;
  for (const FullPath& p : paths) point += p.point_light;
  EXPECT_GT(point, 20u);
  check_weights(scene, paths);
}

// ---------------------------------------------------------------------------------------------
// Connections

// connect(), unweighted, is f(z) / p_s for every strategy of the path; weighted, it is that
// times mis_weight.
void check_connections(const Scene& scene, const std::vector<FullPath>& paths) {
  const StrategyCounts counts = make_scene_estimator("plain")->strategy_counts(scene);
  std::size_t checked = 0;
  for (std::size_t n = 0; n < paths.size(); ++n) {
    const FullPath& p = paths[n];
    const PathFacts f = facts(scene, p);
    if (!usable(f)) continue;
    for (std::size_t s = 0; s <= p.k(); ++s) {
      if (!possible(p, s)) continue;
      SCOPED_TRACE("path " + std::to_string(n) + " k " + std::to_string(p.k()) + " s " +
                   std::to_string(s));
      const Split parts = split(scene, p, f, s);
      TraceCounters counters;
      std::optional<PixelPosition> pixel;
      const Rgb value = connect(scene, parts.light, parts.camera, counts,
                                {.visibility = false, .weighted = false}, counters, &pixel);
      const Rgb expected = f.contribution / strategy_pdf(f, s);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(value[c], expected[c], 1e-9 * expected.max_channel()) << "channel " << c;
      }
      if (parts.camera.size() == 1) {
        const auto where = scene.camera().project(unit(p.z[0].position, p.z[1].position));
        ASSERT_TRUE(pixel && where);
        EXPECT_EQ(pixel->x, where->x);
        EXPECT_EQ(pixel->y, where->y);
      }
      const Rgb weighted =
          connect(scene, parts.light, parts.camera, counts, {.visibility = false}, counters);
      const double w = mis_weight(scene, parts.light, parts.camera, counts);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(weighted[c], w * value[c], 1e-12 * value[c]);
      ++checked;
    }
  }
  EXPECT_GT(checked, paths.size());
}

TEST(SceneMisConnect, UnweightedValueIsContributionOverPdf) {
  const Scene glossy = scene_named("cornell-glossy");
  check_connections(glossy, camera_paths(glossy, 60, 500));
  const Scene point(cornell_with_point_light());
  check_connections(point, light_paths(point, 60, 600));
}

// ---------------------------------------------------------------------------------------------
// The walks' own bookkeeping

bool near_relative(double a, double b, double tolerance) {
  return std::abs(a - b) <= tolerance * std::max(std::abs(a), std::abs(b));
}

// What trace_camera_path and trace_light_path recorded on their vertices matches the densities
// and throughputs computed from the positions: pdf_fwd everywhere, pdf_rev where the walk
// knew the vertex two steps on, beta everywhere.
void check_walk(const Scene& scene, const std::vector<FullPath>& paths) {
  int mismatches = 0, checked = 0;
  for (const FullPath& p : paths) {
    const PathFacts f = facts(scene, p);
    if (!usable(f)) continue;
    const std::size_t k = p.k();
    for (std::size_t i = 1; i <= k; ++i) {
      const PathVertex& v = p.z[i];
      const Rgb beta = p.from_camera ? f.camera_beta[i] : f.light_beta[i];
      const double fwd = p.from_camera ? f.camera_pdf[i] : f.light_pdf[i];
      bool ok = near_relative(v.pdf_fwd, fwd, 1e-9);
      for (int c = 0; c < 3; ++c) ok = ok && near_relative(v.beta[c], beta[c], 1e-9);
      // The reverse density needs the vertex after the next one in the walk's direction.
      if (p.from_camera && i + 2 <= k) ok = ok && near_relative(v.pdf_rev, f.light_pdf[i], 1e-9);
      if (!p.from_camera && i >= 3) ok = ok && near_relative(v.pdf_rev, f.camera_pdf[i], 1e-9);
      if (!ok) {
        ADD_FAILURE() << "vertex " << i << " of " << k << ": pdf_fwd " << v.pdf_fwd << " vs " << fwd
                      << ", pdf_rev " << v.pdf_rev << ", beta " << v.beta.r << " vs " << beta.r;
        if (++mismatches > 5) return;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(SceneMisWalk, RecordedDensitiesMatchThePath) {
  const Scene glossy = scene_named("cornell-glossy");
  check_walk(glossy, camera_paths(glossy, 100, 700));
  const Scene point(cornell_with_point_light());
  check_walk(point, light_paths(point, 100, 800));
}

// ---------------------------------------------------------------------------------------------
// The furnace renders to its exact radiance

constexpr std::uint32_t kReplicates = 8;
constexpr std::uint32_t kIterations = 4;

SceneDescription small_furnace() {
  SceneDescription d = *built_in_scene("furnace");
  d.width = d.height = 8;
  d.max_length = 3;
  return d;
}

// The honest estimators' furnace renders, as their entries declare them (smaller pools than
// their defaults, an 8×8 image needs fewer; pcbpt's ablations): at its defaults an entry that
// declares none.
std::vector<NamedEstimator> render_configs() {
  std::vector<NamedEstimator> out;
  for (const EstimatorEntry* e : scene_entries()) {
    if (e->biased) continue;
    if (e->scene_tests.renders.empty()) out.push_back(make(*e, {}));
    for (const NamedParams& config : e->scene_tests.renders) out.push_back(make(*e, config));
  }
  return out;
}

TEST(SceneRenderFurnace, EveryMethodIsUnbiased) {
  const Scene scene(small_furnace());
  const Rgb reference = furnace_radiance(3);
  const std::vector<NamedEstimator> methods = render_configs();
  // The error budget above: every configuration's 3 channels at p > 1e-4 stay within 1%.
  EXPECT_LE(3 * methods.size() * 1e-4, 0.01) << methods.size() << " configurations";
  for (const NamedEstimator& method : methods) {
    SCOPED_TRACE(method.name);
    // Per replicate and channel, the image's mean over all pixels.
    std::vector<Rgb> means;
    for (std::uint32_t r = 0; r < kReplicates; ++r) {
      const Image image = render_replicate(scene, *method.estimator, 77, r, kIterations).image;
      Rgb sum;
      for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        sum += {image.values[3 * i], image.values[3 * i + 1], image.values[3 * i + 2]};
      }
      means.push_back(sum / static_cast<double>(image.pixel_count()));
    }
    for (int c = 0; c < 3; ++c) {
      double mean = 0.0, squares = 0.0;
      for (const Rgb& m : means) mean += m[c];
      mean /= kReplicates;
      for (const Rgb& m : means) squares += (m[c] - mean) * (m[c] - mean);
      const double stderr_of_mean = std::sqrt(squares / (kReplicates - 1) / kReplicates);
      // Some estimators are nearly exact here; a difference at rounding level is no bias.
      const bool exact = std::abs(mean - reference[c]) <= 1e-9 * reference[c];
      const double p =
          exact ? 1.0
                : student_t_p_value((mean - reference[c]) / stderr_of_mean, kReplicates - 1.0);
      EXPECT_GT(p, 1e-4) << "channel " << c << ": mean " << mean << " ± " << stderr_of_mean
                         << ", exact " << reference[c];
    }
  }
}

TEST(SceneRenderFurnace, ThreadCountDoesNotChangeTheImage) {
  const Scene scene(small_furnace());
  for (const NamedEstimator& method : render_configs()) {
    SCOPED_TRACE(method.name);
    std::vector<double> images[2];
    for (int threads : {1, 2}) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(threads));
      images[threads - 1] = render_replicate(scene, *method.estimator, 99, 3, 2).image.values;
    }
    ASSERT_EQ(images[0].size(), images[1].size());
    EXPECT_EQ(std::memcmp(images[0].data(), images[1].data(), images[0].size() * sizeof(double)),
              0);
  }
}

// ---------------------------------------------------------------------------------------------
// A scene control's mistake, exactly

// ctl-scene-nee-count is pt with its next-event estimates divided by 1 + severity: at severity 0
// it renders pt's image bit for bit; at any other severity, from the same streams, its emitter
// hits (s = 0) are pt's and its next-event layers (s = 1) pt's divided by 1 + severity, so the
// image lies between pt's / (1 + severity) and pt's.
TEST(SceneRenderControl, NeeCountIsPtWithItsNextEventsDivided) {
  SceneDescription d = *built_in_scene("cornell");
  d.width = d.height = 8;
  d.max_length = 3;
  const Scene scene(d);
  const auto render = [&](const std::shared_ptr<const SceneEstimator>& estimator) {
    return render_replicate(scene, *estimator, 55, 2, 2, nullptr, true);
  };
  const ReplicateImage pt = render(make_scene_estimator("pt"));
  const ReplicateImage zero =
      render(make_scene_estimator("ctl-scene-nee-count", {{"severity", "0"}}));
  ASSERT_EQ(zero.image.values.size(), pt.image.values.size());
  EXPECT_EQ(std::memcmp(zero.image.values.data(), pt.image.values.data(),
                        pt.image.values.size() * sizeof(double)),
            0);

  const double severity = 0.25;
  const ReplicateImage off =
      render(make_scene_estimator("ctl-scene-nee-count", {{"severity", "0.25"}}));
  ASSERT_TRUE(pt.strategies && off.strategies);
  ASSERT_EQ(off.strategies->layers.size(), pt.strategies->layers.size());
  double next_event = 0.0;
  for (std::size_t l = 0; l < pt.strategies->layers.size(); ++l) {
    const StrategyLayer& a = pt.strategies->layers[l];
    const StrategyLayer& b = off.strategies->layers[l];
    ASSERT_EQ(a.s, b.s);
    ASSERT_EQ(a.t, b.t);
    const double scale = a.s == 1 ? 1.0 / (1.0 + severity) : 1.0;
    for (std::size_t i = 0; i < a.image.values.size(); ++i) {
      EXPECT_NEAR(b.image.values[i], scale * a.image.values[i], 1e-12 * a.image.values[i])
          << "s" << a.s << "_t" << a.t << " value " << i;
      if (a.s == 1) next_event += a.image.values[i];
    }
  }
  EXPECT_GT(next_event, 0.0);
  double sum_pt = 0.0, sum_off = 0.0;
  for (std::size_t i = 0; i < pt.image.values.size(); ++i) {
    sum_pt += pt.image.values[i];
    sum_off += off.image.values[i];
    EXPECT_LE(off.image.values[i], pt.image.values[i] * (1.0 + 1e-12));
    EXPECT_GE(off.image.values[i], pt.image.values[i] / (1.0 + severity) * (1.0 - 1e-12));
  }
  EXPECT_LT(sum_off, sum_pt);
}

}  // namespace
}  // namespace pcbench::scene
