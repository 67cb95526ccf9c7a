#include "integrands/scenes/bsdf.h"

#include <cmath>

namespace pcbench::scene {
namespace {

// The normal turned to the side of `wo`.
Vec3 facing(const Vec3& normal, const Vec3& wo) {
  return dot(normal, wo) < 0.0 ? -normal : normal;
}

bool same_side(const Vec3& n, const Vec3& wo, const Vec3& wi) {
  return dot(n, wo) > 0.0 && dot(n, wi) > 0.0;
}

// cos^exponent of the angle between wi and the mirror direction of wo, 0 past 90 degrees.
double phong_lobe(const Material& m, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  const double c = dot(reflect(wo, n), wi);
  return c > 0.0 ? std::pow(c, m.exponent) : 0.0;
}

// The Phong BSDF's value and density for a lobe value cos^e α.
Rgb phong_f(const Material& m, double lobe) {
  return m.albedo * ((m.exponent + 2.0) * (0.5 * kInvPi) * lobe);
}
double phong_pdf(const Material& m, double lobe) {
  return (m.exponent + 1.0) * (0.5 * kInvPi) * lobe;
}

}  // namespace

bool is_delta(const Material& material) {
  return material.kind == MaterialKind::kMirror;
}

Vec3 sample_cosine_hemisphere(const Vec3& normal, double u1, double u2) {
  const double r = std::sqrt(u1);
  const double phi = 2.0 * kPi * u2;
  const Vec3 local{r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u1))};
  return Frame(normal).to_world(local);
}

Rgb bsdf_eval(const Material& material, const Vec3& normal, const Vec3& wo, const Vec3& wi) {
  const Vec3 n = facing(normal, wo);
  if (!same_side(n, wo, wi)) return {};
  switch (material.kind) {
    case MaterialKind::kDiffuse:
      return material.albedo * kInvPi;
    case MaterialKind::kPhong:
      return phong_f(material, phong_lobe(material, n, wo, wi));
    case MaterialKind::kMirror:
      return {};
  }
  return {};
}

double bsdf_pdf(const Material& material, const Vec3& normal, const Vec3& wo, const Vec3& wi) {
  const Vec3 n = facing(normal, wo);
  switch (material.kind) {
    case MaterialKind::kDiffuse:
      return same_side(n, wo, wi) ? dot(n, wi) * kInvPi : 0.0;
    case MaterialKind::kPhong:
      // The lobe is sampled in full (also below the surface, where the sample is then
      // invalid), so the density does not depend on which side wi is on.
      return phong_pdf(material, phong_lobe(material, n, wo, wi));
    case MaterialKind::kMirror:
      return 0.0;
  }
  return 0.0;
}

BsdfValue bsdf_value(const Material& material, const Vec3& normal, const Vec3& wo, const Vec3& wi) {
  const Vec3 n = facing(normal, wo);
  const bool same = same_side(n, wo, wi);
  switch (material.kind) {
    case MaterialKind::kDiffuse:
      // Off the same side, both densities are 0 as well: wo then lies below wi's side too.
      if (!same) return {};
      return {material.albedo * kInvPi, dot(n, wi) * kInvPi, dot(n, wo) * kInvPi};
    case MaterialKind::kPhong: {
      // The lobe is symmetric in wo and wi (reflect does not depend on the normal's sign), so
      // both densities are one.
      const double lobe = phong_lobe(material, n, wo, wi);
      const double pdf = phong_pdf(material, lobe);
      return {same ? phong_f(material, lobe) : Rgb{}, pdf, pdf};
    }
    case MaterialKind::kMirror:
      return {};
  }
  return {};
}

BsdfSample bsdf_sample(const Material& material, const Vec3& normal, const Vec3& wo, double u1,
                       double u2) {
  const Vec3 n = facing(normal, wo);
  BsdfSample s;
  switch (material.kind) {
    case MaterialKind::kDiffuse:
      s.wi = sample_cosine_hemisphere(n, u1, u2);
      break;
    case MaterialKind::kPhong: {
      // cos α distributed with density ∝ cos^e α about the mirror direction.
      const double cos_alpha = std::pow(1.0 - u1, 1.0 / (material.exponent + 1.0));
      const double sin_alpha = std::sqrt(std::max(0.0, 1.0 - cos_alpha * cos_alpha));
      const double phi = 2.0 * kPi * u2;
      s.wi = Frame(reflect(wo, n))
                 .to_world({sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), cos_alpha});
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

}  // namespace pcbench::scene
