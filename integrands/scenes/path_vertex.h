// Subpath vertices and the random walks that make camera and light subpaths.
//
// Each vertex keeps the throughput of its subpath (contribution / pdf, in the solid-angle product
// form) and two area densities for the MIS weights: pdf_fwd, of sampling it from its
// predecessor in its own subpath, and pdf_rev, of sampling it from its successor walking the
// other way (Veach's thesis, ch. 10; the same bookkeeping as pbrt-v4's BDPT).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "base/rng.h"
#include "integrands/scenes/scene.h"
#include "integrands/scenes/turn_trig.h"

namespace pcbench::scene {

enum class VertexKind : std::uint8_t { kCamera, kEmitter, kSurface };

// The small members first, so that the vertex fills two cache lines (128 bytes) exactly.
struct PathVertex {
  VertexKind kind = VertexKind::kSurface;
  bool delta = false;        // specular scattering here
  bool point_light = false;  // an emitter vertex that is a point light (a delta position)
  std::uint32_t triangle = 0;
  Vec3 position = {};
  Vec3 normal = {};       // geometric normal; zero at the camera and at a point light
  Vec3 to_previous = {};  // unit direction to the previous vertex of its subpath
  Rgb beta = {};          // subpath throughput up to this vertex
  double pdf_fwd = 0.0;
  double pdf_rev = 0.0;
  // The balance heuristic's sum over the strategies whose join lies before this vertex in its
  // own subpath, relative to the one that joins right after it, which makes a weight's cost
  // independent of the path's length (store_camera_weight_sums in connection.h); NaN until
  // stored, and a weight then loops over the subpath.
  double weight_sum = std::numeric_limits<double>::quiet_NaN();
};
static_assert(sizeof(PathVertex) == 128);

// Work the walks and the connections did, summed into the report's counters.
struct TraceCounters {
  std::uint64_t light_paths = 0;     // light subpaths traced
  std::uint64_t camera_rays = 0;     // closest-hit rays of camera subpaths (primary included)
  std::uint64_t light_rays = 0;      // closest-hit rays of light subpaths
  std::uint64_t shadow_rays = 0;     // occlusion rays of connections
  std::uint64_t connections = 0;     // connections evaluated (splats included)
  std::uint64_t occluded = 0;        // connections a shadow ray found blocked
  std::uint64_t skipped_zero = 0;    // no shadow ray: the unoccluded value was already 0
  std::uint64_t skipped_convex = 0;  // no shadow ray: the scene is a convex enclosure
  std::uint64_t splats = 0;          // light-tracing contributions that reached a pixel

  void add(const TraceCounters& o) {
    light_paths += o.light_paths;
    camera_rays += o.camera_rays;
    light_rays += o.light_rays;
    shadow_rays += o.shadow_rays;
    connections += o.connections;
    occluded += o.occluded;
    skipped_zero += o.skipped_zero;
    skipped_convex += o.skipped_convex;
    splats += o.splats;
  }
};

// A subpath's walk between two rays: where it goes next and what it carries.
struct Walk {
  Vec3 direction;                // of the next ray, from the path's last vertex
  double direction_pdf = 0.0;    // its solid-angle density
  Rgb beta;                      // the throughput the next vertex will carry
  std::size_t max_vertices = 0;  // the walk stops when the path has this many
  bool previous_delta = false;   // the last vertex scattered specularly
};

// The first vertex of a camera subpath through film position (fx, fy), y0, and its walk (path
// cleared first).
Walk start_camera_path(const Scene& scene, double fx, double fy, std::uint32_t max_length,
                       std::vector<PathVertex>& path);
// The first vertex of a light subpath, x0 from `rng`, and its walk, or none when it ends there
// (path cleared first).
std::optional<Walk> start_light_path(const Scene& scene, RandomStream& rng,
                                     std::uint32_t max_length, std::vector<PathVertex>& path,
                                     TraceCounters& counters);
// One step of a walk whose ray hit `hit`: adds the vertex and samples the next direction from
// `rng`. False when the walk ends here (the path is full, or the sample is invalid or black).
// The walks below are this step after each ray.
bool walk_step(const Scene& scene, RandomStream& rng, const Hit& hit, std::vector<PathVertex>& path,
               Walk& walk);
// walk_step in two halves, for the lanes of path_lanes.h, which sample a round's azimuths
// together in between: walk_arrive adds the vertex, false when the path is then full;
// walk_scatter samples the next direction from u1 and the azimuth cos_sin_of_turn(u2) of the
// step's two uniforms, false when the walk ends there.
bool walk_arrive(const Scene& scene, const Hit& hit, std::vector<PathVertex>& path,
                 const Walk& walk);
bool walk_scatter(const Scene& scene, const Hit& hit, double u1, CosSin azimuth,
                  std::vector<PathVertex>& path, Walk& walk);

// Camera subpath through film position (fx, fy): y0 at the camera, then up to
// max_length surface vertices. Clears `path` first.
void trace_camera_path(const Scene& scene, double fx, double fy, RandomStream& rng,
                       std::uint32_t max_length, std::vector<PathVertex>& path,
                       TraceCounters& counters);

// Light subpath: x0 on an emitter, then up to max_length - 1 surface vertices (a light subpath
// of s vertices connects to the camera in a path of s segments). Clears `path` first.
void trace_light_path(const Scene& scene, RandomStream& rng, std::uint32_t max_length,
                      std::vector<PathVertex>& path, TraceCounters& counters);

// One emitter vertex alone (path tracing's next-event estimation).
PathVertex sample_emitter_vertex(const Scene& scene, RandomStream& rng);
// The vertex of emitter point `e` (what sample_emitter_vertex makes of the point it samples).
PathVertex emitter_vertex(const EmitterPoint& e);
// The emitter point of a vertex emitter_vertex made: emitter_vertex(emitter_point(scene, v)) is v.
EmitterPoint emitter_point(const Scene& scene, const PathVertex& v);

// Solid-angle density of emission from emitter point v in unit direction w: cosine-weighted
// into the front of a triangle, uniform for a point light.
double emission_pdf(const PathVertex& v, const Vec3& w);

// Radiance emitted from emitter point `v` (on triangle or point light) in `direction` (any
// length: only its side of the triangle matters).
Rgb emitted_towards(const Scene& scene, const PathVertex& v, const Vec3& direction);

// |cos| at v of the direction to `target`; 1 at a point light or the camera.
inline double abs_cos_at(const PathVertex& v, const Vec3& direction) {
  if (v.kind == VertexKind::kCamera || v.point_light) return 1.0;
  return std::abs(dot(v.normal, direction));
}

}  // namespace pcbench::scene
