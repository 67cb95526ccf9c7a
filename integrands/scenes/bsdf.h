// Scattering at a surface point: evaluation, sampling and the solid-angle pdf of the three
// materials (scene_description.h). Surfaces scatter on both sides: the normal is flipped to the
// side of `wo` first, and light passing to the other side is not scattered (no transmission).
//
// Directions point away from the surface. f is symmetric in (wo, wi); the pdf is not (the
// diffuse one is cos θi / π), so a reverse density is asked for with the arguments swapped, as
// path_vertex.cpp does.
#pragma once

#include <cmath>

#include "integrands/scenes/scene_description.h"
#include "integrands/scenes/scene_math.h"
#include "integrands/scenes/turn_trig.h"

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
inline Rgb bsdf_eval(const Material& material, const Vec3& normal, const Vec3& wo, const Vec3& wi);

// Density with respect to solid angle of sampling wi given wo; 0 for a mirror.
inline double bsdf_pdf(const Material& material, const Vec3& normal, const Vec3& wo,
                       const Vec3& wi);

// f(wo, wi) with both densities, bsdf_pdf(wo, wi) and bsdf_pdf(wi, wo), sharing their work (a
// connection needs all three at each end).
struct BsdfValue {
  Rgb f = {};
  double pdf = 0.0;          // of sampling wi given wo
  double pdf_reverse = 0.0;  // of sampling wo given wi
};
inline BsdfValue bsdf_value(const Material& material, const Vec3& normal, const Vec3& wo,
                            const Vec3& wi);

// Samples wi given wo from two uniforms. The second form takes u2 as its azimuth,
// cos_sin_of_turn(u2), computed beforehand: a round of walks in lanes computes them together
// (cos_sin_of_turns).
inline BsdfSample bsdf_sample(const Material& material, const Vec3& normal, const Vec3& wo,
                              double u1, double u2);
inline BsdfSample bsdf_sample(const Material& material, const Vec3& normal, const Vec3& wo,
                              double u1, CosSin azimuth);

// A direction with density cos θ / π about `normal` (which must be a unit vector); the second
// form with u2's azimuth given, as bsdf_sample's.
inline Vec3 sample_cosine_hemisphere(const Vec3& normal, double u1, double u2);
inline Vec3 sample_cosine_hemisphere(const Vec3& normal, double u1, CosSin azimuth);

inline bool is_delta(const Material& material);

// The definitions, inline: connections and walks call them once per vertex, and out of line their
// results came back through memory, where reading them stalled on the store (a failed
// store-to-load forward) in `connect` and `random_walk`.

namespace bsdf_detail {

// The normal turned to the side of `wo`.
inline Vec3 facing(const Vec3& normal, const Vec3& wo) {
  return dot(normal, wo) < 0.0 ? -normal : normal;
}

inline bool same_side(const Vec3& n, const Vec3& wo, const Vec3& wi) {
  return dot(n, wo) > 0.0 && dot(n, wi) > 0.0;
}

// cos^exponent of the angle between wi and the mirror direction of wo, 0 past 90 degrees.
inline double phong_lobe(const Material& m, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  const double c = dot(reflect(wo, n), wi);
  return c > 0.0 ? std::pow(c, m.exponent) : 0.0;
}

// The Phong BSDF's value and density for a lobe value cos^e α.
inline Rgb phong_f(const Material& m, double lobe) {
  return m.albedo * ((m.exponent + 2.0) * (0.5 * kInvPi) * lobe);
}
inline double phong_pdf(const Material& m, double lobe) {
  return (m.exponent + 1.0) * (0.5 * kInvPi) * lobe;
}

}  // namespace bsdf_detail

inline bool is_delta(const Material& material) {
  return material.kind == MaterialKind::kMirror;
}

inline Vec3 sample_cosine_hemisphere(const Vec3& normal, double u1, CosSin azimuth) {
  const double r = std::sqrt(u1);
  const Vec3 local{r * azimuth.cos, r * azimuth.sin, std::sqrt(std::max(0.0, 1.0 - u1))};
  return Frame(normal).to_world(local);
}
inline Vec3 sample_cosine_hemisphere(const Vec3& normal, double u1, double u2) {
  return sample_cosine_hemisphere(normal, u1, cos_sin_of_turn(u2));
}

inline Rgb bsdf_eval(const Material& material, const Vec3& normal, const Vec3& wo, const Vec3& wi) {
  const Vec3 n = bsdf_detail::facing(normal, wo);
  if (!bsdf_detail::same_side(n, wo, wi)) return {};
  switch (material.kind) {
    case MaterialKind::kDiffuse:
      return material.albedo * kInvPi;
    case MaterialKind::kPhong:
      return bsdf_detail::phong_f(material, bsdf_detail::phong_lobe(material, n, wo, wi));
    case MaterialKind::kMirror:
      return {};
  }
  return {};
}

inline double bsdf_pdf(const Material& material, const Vec3& normal, const Vec3& wo,
                       const Vec3& wi) {
  const Vec3 n = bsdf_detail::facing(normal, wo);
  switch (material.kind) {
    case MaterialKind::kDiffuse:
      return bsdf_detail::same_side(n, wo, wi) ? dot(n, wi) * kInvPi : 0.0;
    case MaterialKind::kPhong:
      // The lobe is sampled in full (also below the surface, where the sample is then
      // invalid), so the density does not depend on which side wi is on.
      return bsdf_detail::phong_pdf(material, bsdf_detail::phong_lobe(material, n, wo, wi));
    case MaterialKind::kMirror:
      return 0.0;
  }
  return 0.0;
}

inline BsdfValue bsdf_value(const Material& material, const Vec3& normal, const Vec3& wo,
                            const Vec3& wi) {
  const Vec3 n = bsdf_detail::facing(normal, wo);
  const bool same = bsdf_detail::same_side(n, wo, wi);
  switch (material.kind) {
    case MaterialKind::kDiffuse:
      // Off the same side, both densities are 0 as well: wo then lies below wi's side too.
      if (!same) return {};
      return {material.albedo * kInvPi, dot(n, wi) * kInvPi, dot(n, wo) * kInvPi};
    case MaterialKind::kPhong: {
      // The lobe is symmetric in wo and wi (reflect does not depend on the normal's sign), so
      // both densities are one.
      const double lobe = bsdf_detail::phong_lobe(material, n, wo, wi);
      const double pdf = bsdf_detail::phong_pdf(material, lobe);
      return {same ? bsdf_detail::phong_f(material, lobe) : Rgb{}, pdf, pdf};
    }
    case MaterialKind::kMirror:
      return {};
  }
  return {};
}

inline BsdfSample bsdf_sample(const Material& material, const Vec3& normal, const Vec3& wo,
                              double u1, CosSin azimuth) {
  const Vec3 n = bsdf_detail::facing(normal, wo);
  BsdfSample s;
  switch (material.kind) {
    case MaterialKind::kDiffuse:
      s.wi = sample_cosine_hemisphere(n, u1, azimuth);
      break;
    case MaterialKind::kPhong: {
      // cos α distributed with density ∝ cos^e α about the mirror direction.
      const double cos_alpha = std::pow(1.0 - u1, 1.0 / (material.exponent + 1.0));
      const double sin_alpha = std::sqrt(std::max(0.0, 1.0 - cos_alpha * cos_alpha));
      s.wi = Frame(reflect(wo, n))
                 .to_world({sin_alpha * azimuth.cos, sin_alpha * azimuth.sin, cos_alpha});
      break;
    }
    case MaterialKind::kMirror: {
      s.wi = reflect(wo, n);
      s.delta = true;
      s.pdf = 1.0;
      const double cos_i = dot(n, s.wi);
      s.valid = cos_i > 0.0;
      s.f = s.valid ? material.albedo / cos_i : Rgb{};
      return s;
    }
  }
  s.pdf = bsdf_pdf(material, n, wo, s.wi);
  s.f = bsdf_eval(material, n, wo, s.wi);
  s.valid = s.pdf > 0.0 && dot(n, s.wi) > 0.0;
  return s;
}

inline BsdfSample bsdf_sample(const Material& material, const Vec3& normal, const Vec3& wo,
                              double u1, double u2) {
  return bsdf_sample(material, normal, wo, u1, cos_sin_of_turn(u2));
}

}  // namespace pcbench::scene
