// Scattering at a surface point: evaluation, sampling and the solid-angle pdf of the three
// materials (scene_description.h). Surfaces scatter on both sides: the normal is flipped to the
// side of `wo` first, and light passing to the other side is not scattered (no transmission).
//
// Directions point away from the surface. f is symmetric in (wo, wi); the pdf is not (the
// diffuse one is cos θi / π), so a reverse density is asked for with the arguments swapped, as
// path_vertex.cpp does.
#pragma once

#include "integrands/scenes/scene_description.h"
#include "integrands/scenes/scene_math.h"

namespace pcbench::scene {

struct BsdfSample {
  Vec3 wi = {};
  Rgb f = {};        // the BSDF value; for a mirror, albedo / |cos wi| (so f |cos| / pdf = albedo)
  double pdf = 0.0;  // solid angle density of wi; 1 for a mirror (a delta, not a density)
  bool delta = false;  // a specular (Dirac) direction
  bool valid = false;  // false when the sampled direction leaves no reflection (below the surface)
};

// f(wo, wi): 0 for a mirror (a delta is never hit by chance) and when wo and wi lie on
// opposite sides of the surface.
Rgb bsdf_eval(const Material& material, const Vec3& normal, const Vec3& wo, const Vec3& wi);

// Density with respect to solid angle of sampling wi given wo; 0 for a mirror.
double bsdf_pdf(const Material& material, const Vec3& normal, const Vec3& wo, const Vec3& wi);

// f(wo, wi) with both densities, bsdf_pdf(wo, wi) and bsdf_pdf(wi, wo), sharing their work (a
// connection needs all three at each end).
struct BsdfValue {
  Rgb f = {};
  double pdf = 0.0;          // of sampling wi given wo
  double pdf_reverse = 0.0;  // of sampling wo given wi
};
BsdfValue bsdf_value(const Material& material, const Vec3& normal, const Vec3& wo, const Vec3& wi);

// Samples wi given wo from two uniforms.
BsdfSample bsdf_sample(const Material& material, const Vec3& normal, const Vec3& wo, double u1,
                       double u2);

// A direction with density cos θ / π about `normal` (which must be a unit vector).
Vec3 sample_cosine_hemisphere(const Vec3& normal, double u1, double u2);

bool is_delta(const Material& material);

}  // namespace pcbench::scene
