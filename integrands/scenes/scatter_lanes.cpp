#include "integrands/scenes/scatter_lanes.h"

#include <algorithm>
#include <cmath>

#include "base/lane_select.h"
#include "integrands/scenes/bsdf.h"

namespace pcbench::scene {
namespace {

constexpr std::size_t kChunk = 64;

// A chunk's lanes in structure-of-arrays form.
struct Chunk {
  std::size_t size = 0;
  // Gathered.
  double n_x[kChunk], n_y[kChunk], n_z[kChunk];     // the vertex's geometric normal
  double wo_x[kChunk], wo_y[kChunk], wo_z[kChunk];  // its to_previous
  double u1[kChunk], cos[kChunk], sin[kChunk];      // the step's uniform and azimuth
  double b_r[kChunk], b_g[kChunk], b_b[kChunk];     // the walk's beta; the new one out
  double a_r[kChunk], a_g[kChunk], a_b[kChunk];     // the surface's albedo
  double before_cos[kChunk];                        // abs_cos_at(the vertex before, to_previous)
  double distance[kChunk];                          // the hit's
  // Computed.
  double wi_x[kChunk], wi_y[kChunk], wi_z[kChunk];
  double pdf[kChunk], pdf_rev[kChunk];
  double valid[kChunk];  // 1: walk_scatter's sample valid (its beta then updated)
  double goes[kChunk];   // 1: and the new beta not black
};

// walk_scatter's arithmetic for a Lambertian vertex, lane by lane: the direction by bsdf.h's own
// inline facing and sample_cosine_hemisphere (which vectorise), the densities and f as
// bsdf_pdf's and bsdf_eval's Lambertian branches compute them.
[[gnu::target_clones("avx512f", "avx2", "default")]] void scatter(Chunk& c) {
  for (std::size_t j = 0; j < c.size; ++j) {
    const Vec3 normal{c.n_x[j], c.n_y[j], c.n_z[j]};
    const Vec3 wo{c.wo_x[j], c.wo_y[j], c.wo_z[j]};
    // The normal on wo's side (facing it again, as bsdf_pdf and bsdf_eval do, leaves it).
    const Vec3 n = bsdf_detail::facing(normal, wo);
    const Vec3 wi = sample_cosine_hemisphere(n, c.u1[j], {c.cos[j], c.sin[j]});
    // bsdf_pdf's and bsdf_eval's Lambertian branches at n, and the sample's validity; their
    // same-side test with & (bsdf_detail::same_side's && is a branch, which stops the vectoriser).
    const double n_wi = dot(n, wi);
    const bool same = (dot(n, wo) > 0.0) & (n_wi > 0.0);
    const double pdf = lane_select(same, n_wi * kInvPi, 0.0);
    const bool valid = (pdf > 0.0) & (n_wi > 0.0);
    const double f_r = lane_select(same, c.a_r[j] * kInvPi, 0.0);
    const double f_g = lane_select(same, c.a_g[j] * kInvPi, 0.0);
    const double f_b = lane_select(same, c.a_b[j] * kInvPi, 0.0);
    // walk_scatter: the throughput, and the density of walking back at the vertex before.
    const double q = std::abs(dot(wi, normal)) / lane_select(valid, pdf, 1.0);
    const double beta_r = c.b_r[j] * f_r * q;
    const double beta_g = c.b_g[j] * f_g * q;
    const double beta_b = c.b_b[j] * f_b * q;
    const bool black = (beta_r == 0.0) & (beta_g == 0.0) & (beta_b == 0.0);
    const Vec3 n_back = bsdf_detail::facing(normal, wi);  // bsdf_pdf(normal, wi, wo)'s
    const double n_back_wo = dot(n_back, wo);
    const bool back_same = (dot(n_back, wi) > 0.0) & (n_back_wo > 0.0);
    const double pdf_back = lane_select(back_same, n_back_wo * kInvPi, 0.0);
    const double inv_distance_squared = 1.0 / (c.distance[j] * c.distance[j]);
    c.b_r[j] = lane_select(valid, beta_r, c.b_r[j]);
    c.b_g[j] = lane_select(valid, beta_g, c.b_g[j]);
    c.b_b[j] = lane_select(valid, beta_b, c.b_b[j]);
    c.wi_x[j] = wi.x;
    c.wi_y[j] = wi.y;
    c.wi_z[j] = wi.z;
    c.pdf[j] = pdf;
    c.pdf_rev[j] = pdf_back * c.before_cos[j] * inv_distance_squared;
    c.valid[j] = valid ? 1.0 : 0.0;
    c.goes[j] = (valid & !black) ? 1.0 : 0.0;
  }
}

}  // namespace

void scatter_lambertian(const Scene& scene, std::span<WalkLane> lanes, LaneBuffers& buffers) {
  const std::span<const std::uint32_t> lambertian = buffers.lambertian;
  // The lane of the round's scattering lane j.
  auto lane_of = [&](std::uint32_t j) -> WalkLane& {
    return lanes[buffers.active[buffers.scattering[j]]];
  };
  Chunk c;
  for (std::size_t first = 0; first < lambertian.size(); first += kChunk) {
    c.size = std::min(kChunk, lambertian.size() - first);
    for (std::size_t i = 0; i < c.size; ++i) {
      const std::uint32_t j = lambertian[first + i];
      const WalkLane& lane = lane_of(j);
      const std::vector<PathVertex>& path = *lane.path;
      const PathVertex& current = path.back();
      c.n_x[i] = current.normal.x, c.n_y[i] = current.normal.y, c.n_z[i] = current.normal.z;
      c.wo_x[i] = current.to_previous.x, c.wo_y[i] = current.to_previous.y,
      c.wo_z[i] = current.to_previous.z;
      c.u1[i] = buffers.u1[j], c.cos[i] = buffers.cos[j], c.sin[i] = buffers.sin[j];
      c.b_r[i] = lane.walk.beta.r, c.b_g[i] = lane.walk.beta.g, c.b_b[i] = lane.walk.beta.b;
      const Rgb& albedo = scene.material(current.triangle).albedo;
      c.a_r[i] = albedo.r, c.a_g[i] = albedo.g, c.a_b[i] = albedo.b;
      c.before_cos[i] = abs_cos_at(path[path.size() - 2], current.to_previous);
      c.distance[i] = buffers.hits[buffers.scattering[j]].distance;
    }
    scatter(c);
    for (std::size_t i = 0; i < c.size; ++i) {
      const std::uint32_t j = lambertian[first + i];
      WalkLane& lane = lane_of(j);
      buffers.goes[j] = c.goes[i] != 0.0 ? 1 : 0;
      if (c.valid[i] == 0.0) continue;
      lane.walk.beta = {c.b_r[i], c.b_g[i], c.b_b[i]};
      if (c.goes[i] == 0.0) continue;
      std::vector<PathVertex>& path = *lane.path;
      path[path.size() - 2].pdf_rev = c.pdf_rev[i];
      lane.walk.direction = {c.wi_x[i], c.wi_y[i], c.wi_z[i]};
      lane.walk.direction_pdf = c.pdf[i];
      lane.walk.previous_delta = false;
    }
  }
}

}  // namespace pcbench::scene
