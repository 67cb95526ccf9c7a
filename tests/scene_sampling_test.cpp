// The scene code's sampling routines against their own densities: BSDF directions (χ² of the
// sampled directions against bsdf_pdf integrated over bins), emitter points (triangle choice in
// proportion to power, uniform on the triangle) and the pinhole camera (projection back to the
// pixel; pixel_pdf normalised over a pixel's solid angle).
//
// Error budget: every χ² test asserts p > kMinP = 1e-4. There are 20 of them for the BSDFs
// (diffuse and Phong with 3 exponents, 5 directions wo each) and 3 for the emitters, so a correct
// implementation fails one by chance with probability at most 23 × 1e-4 = 2.3e-3 (the 5-sigma
// energy bounds add well under 1e-5). The seeds are fixed: a given build passes or fails
// deterministically.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "base/rng.h"
#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/camera_model.h"
#include "integrands/scenes/emitters.h"
#include "integrands/scenes/scene.h"
#include "integrands/scenes/turn_trig.h"
#include "tests/test_support.h"

namespace pcbench::scene {
namespace {

constexpr double kMinP = 1e-4;

// The unit direction at polar cosine `cos_theta` and azimuth `phi` about `axis`.
Vec3 direction_about(const Vec3& axis, double cos_theta, double phi) {
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return Frame(axis).to_world({sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta});
}

// ---------------------------------------------------------------------------------------------
// BSDFs

// A tilted normal, so that the shading frame is exercised away from the axes.
Vec3 test_normal() {
  return normalize(Vec3{0.3, -0.5, 0.8});
}

struct Outgoing {
  const char* name;
  double cos_theta;  // about test_normal(); negative: wo on the back side
};
// Normal incidence, 45°, 80°, grazing (cos 0.01) and the back side (120°).
constexpr Outgoing kOutgoing[] = {
    {"normal", 1.0}, {"45deg", 0.7071}, {"80deg", 0.17}, {"grazing", 0.01}, {"back", -0.5}};

Vec3 outgoing(const Outgoing& o) {
  return direction_about(test_normal(), o.cos_theta, 0.7);
}

Material diffuse_material() {
  return {"diffuse", MaterialKind::kDiffuse, {0.8, 0.6, 0.4}, 0.0};
}
Material phong_material(double exponent) {
  return {"phong", MaterialKind::kPhong, {0.9, 0.7, 0.5}, exponent};
}

// The normal turned to the side of wo, as bsdf.cpp does.
Vec3 facing(const Vec3& n, const Vec3& wo) {
  return dot(n, wo) < 0.0 ? -n : n;
}

// Where the sampled directions concentrate: diffuse ones with density cos θ / π about the
// (facing) normal, Phong ones ∝ cos^e α about the mirror direction. The bins are equal steps of
// cos^(e+1) (e = 1 for the cosine lobe), over which such a lobe spreads its mass evenly, so that
// no bin is nearly empty even for e = 100.
struct Lobe {
  Vec3 axis;
  double exponent;
};

Lobe lobe_of(const Material& m, const Vec3& normal, const Vec3& wo) {
  const Vec3 n = facing(normal, wo);
  if (m.kind == MaterialKind::kPhong) return {reflect(wo, n), m.exponent};
  return {n, 1.0};
}

constexpr int kCosBins = 16;
constexpr int kPhiBins = 16;
constexpr int kBins = kCosBins * kPhiBins;  // then one bin for invalid samples
constexpr int kSubdivisions = 16;           // midpoint sub-grid per bin and dimension
constexpr std::uint64_t kBsdfSamples = 400000;

// The bin of direction `w` (which must lie in the lobe's hemisphere).
int bin_of(const Lobe& lobe, const Frame& frame, const Vec3& w) {
  const Vec3 local = frame.to_local(w);
  const double t = std::pow(std::clamp(local.z, 0.0, 1.0), lobe.exponent + 1.0);
  double phi = std::atan2(local.y, local.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  const int c = std::min(static_cast<int>(t * kCosBins), kCosBins - 1);
  const int p = std::min(static_cast<int>(phi / (2.0 * kPi) * kPhiBins), kPhiBins - 1);
  return c * kPhiBins + p;
}

// bsdf_pdf integrated over cells of (t = cos^(e+1), φ) about the lobe's axis, where
// dω = dcos dφ = (cos / ((e+1) t)) dt dφ: by the midpoint rule, after splitting every cell the
// surface's horizon crosses (its corners and centre disagree on the side) down to kMaxDepth
// levels, so that the shares above and below the surface are resolved even when the horizon
// passes within a degree of the axis (grazing Phong lobes).
class LobeIntegrator {
 public:
  LobeIntegrator(const Material& m, const Vec3& normal, const Vec3& wo)
      : m_(m), normal_(normal), wo_(wo), lobe_(lobe_of(m, normal, wo)), n_(facing(normal, wo)) {}

  // Adds the mass of cell [t0, t1] × [phi0, phi1] to `above` and `below` the surface.
  void integrate(double t0, double t1, double phi0, double phi1, double& above, double& below,
                 int depth = 0) const {
    const double tm = 0.5 * (t0 + t1), phim = 0.5 * (phi0 + phi1);
    const bool side = is_above(tm, phim);
    if (depth < kMaxDepth && (is_above(t0, phi0) != side || is_above(t0, phi1) != side ||
                              is_above(t1, phi0) != side || is_above(t1, phi1) != side)) {
      for (const auto& [ta, tb] : {std::pair{t0, tm}, std::pair{tm, t1}}) {
        for (const auto& [pa, pb] : {std::pair{phi0, phim}, std::pair{phim, phi1}}) {
          integrate(ta, tb, pa, pb, above, below, depth + 1);
        }
      }
      return;
    }
    const double cos_alpha = std::pow(tm, 1.0 / (lobe_.exponent + 1.0));
    const double jacobian = cos_alpha / ((lobe_.exponent + 1.0) * tm);
    const double mass =
        bsdf_pdf(m_, normal_, wo_, at(tm, phim)) * jacobian * (t1 - t0) * (phi1 - phi0);
    (side ? above : below) += mass;
  }

 private:
  static constexpr int kMaxDepth = 9;

  Vec3 at(double t, double phi) const {
    return direction_about(lobe_.axis, std::pow(t, 1.0 / (lobe_.exponent + 1.0)), phi);
  }
  bool is_above(double t, double phi) const { return dot(n_, at(t, phi)) > 0.0; }

  const Material& m_;
  Vec3 normal_, wo_;
  Lobe lobe_;
  Vec3 n_;
};

// Probability of each bin, and of an invalid sample (below the surface) as the last bin. Also
// returns the total, which is 1 for a density normalised over the lobe's hemisphere.
std::vector<double> bin_probabilities(const Material& m, const Vec3& normal, const Vec3& wo,
                                      double& total) {
  const LobeIntegrator integrator(m, normal, wo);
  std::vector<double> p(kBins + 1, 0.0);
  const double dt = 1.0 / (kCosBins * kSubdivisions);
  const double dphi = 2.0 * kPi / (kPhiBins * kSubdivisions);
  for (int c = 0; c < kCosBins; ++c) {
    for (int q = 0; q < kPhiBins; ++q) {
      for (int a = 0; a < kSubdivisions; ++a) {
        for (int b = 0; b < kSubdivisions; ++b) {
          const double t0 = (c * kSubdivisions + a) * dt;
          const double phi0 = (q * kSubdivisions + b) * dphi;
          integrator.integrate(t0, t0 + dt, phi0, phi0 + dphi, p[c * kPhiBins + q], p[kBins]);
        }
      }
    }
  }
  total = 0.0;
  for (double v : p) total += v;
  return p;
}

// Samples kBsdfSamples directions, checks each against bsdf_pdf / bsdf_eval, bins them and
// estimates ∫ f |cos| dωi per channel (mean and standard error).
struct SampledLobe {
  std::vector<double> counts = std::vector<double>(kBins + 1, 0.0);
  std::uint64_t outside = 0;  // valid samples outside the lobe's hemisphere
  double max_length_error = 0.0, max_pdf_error = 0.0, max_f_error = 0.0;
  Rgb energy, energy_stderr;
};

SampledLobe sample_lobe(const Material& m, const Vec3& normal, const Vec3& wo, std::uint64_t seed) {
  const Lobe lobe = lobe_of(m, normal, wo);
  const Frame frame(lobe.axis);
  RandomStream rng({.key = seed});
  SampledLobe out;
  Rgb sum, sum_squares;
  for (std::uint64_t i = 0; i < kBsdfSamples; ++i) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const BsdfSample s = bsdf_sample(m, normal, wo, u1, u2);
    if (!s.valid) {
      out.counts[kBins] += 1.0;
      continue;
    }
    out.max_length_error = std::max(out.max_length_error, std::abs(length(s.wi) - 1.0));
    const double pdf = bsdf_pdf(m, normal, wo, s.wi);
    out.max_pdf_error = std::max(out.max_pdf_error, std::abs(s.pdf - pdf) / pdf);
    const Rgb f = bsdf_eval(m, normal, wo, s.wi);
    for (int c = 0; c < 3 && f.max_channel() > 0.0; ++c) {
      out.max_f_error = std::max(out.max_f_error, std::abs(s.f[c] - f[c]) / f.max_channel());
    }
    const Rgb weight = s.f * (std::abs(dot(s.wi, normal)) / s.pdf);
    sum += weight;
    sum_squares += weight * weight;
    if (dot(frame.n, s.wi) <= 0.0) {
      ++out.outside;
      continue;
    }
    out.counts[bin_of(lobe, frame, s.wi)] += 1.0;
  }
  const double n = static_cast<double>(kBsdfSamples);
  out.energy = sum / n;
  auto stderr_of = [&](double mean, double mean_square) {
    return std::sqrt(std::max(0.0, mean_square - mean * mean) / n);
  };
  out.energy_stderr = {stderr_of(out.energy.r, sum_squares.r / n),
                       stderr_of(out.energy.g, sum_squares.g / n),
                       stderr_of(out.energy.b, sum_squares.b / n)};
  return out;
}

// The χ² test and the per-sample checks of one material at every kOutgoing direction.
void check_lobe_sampling(const Material& m, std::uint64_t seed) {
  for (const Outgoing& o : kOutgoing) {
    SCOPED_TRACE(std::string("wo ") + o.name);
    const Vec3 wo = outgoing(o);
    double total = 0.0;
    const std::vector<double> p = bin_probabilities(m, test_normal(), wo, total);
    // The density integrates to 1 over the hemisphere about the lobe's axis, which sampling
    // covers (the part below the surface is the invalid share).
    EXPECT_NEAR(total, 1.0, 1e-6);
    const SampledLobe s = sample_lobe(m, test_normal(), wo, seed++);
    EXPECT_EQ(s.outside, 0u);
    EXPECT_LT(s.max_length_error, 1e-12);  // unit directions
    EXPECT_LT(s.max_pdf_error, 1e-12);
    EXPECT_LT(s.max_f_error, 1e-12);
    const double p_value = chi_square_p_value(s.counts, p);
    EXPECT_GT(p_value, kMinP) << "invalid share expected " << p[kBins] << ", observed "
                              << s.counts[kBins] / kBsdfSamples;
    // Energy conservation: ∫ f |cos| dωi <= albedo, within 5 standard errors (and the rounding
    // of a sum of 4e5 terms).
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(s.energy[c], m.albedo[c] * (1.0 + 1e-9) + 5.0 * s.energy_stderr[c])
          << "channel " << c;
    }
    if (m.kind == MaterialKind::kDiffuse) {
      // Every sample is valid and carries the albedo (to rounding).
      EXPECT_EQ(s.counts[kBins], 0.0);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.energy[c], m.albedo[c], 1e-9);
    }
    if (m.kind == MaterialKind::kPhong && o.cos_theta == 1.0) {
      // At normal incidence the whole normalised lobe is above the surface and cos θi = cos α,
      // so ∫ f cos dωi is the albedo exactly.
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(s.energy[c], m.albedo[c], 5.0 * s.energy_stderr[c] + 1e-12) << c;
      }
    }
  }
}

TEST(SceneSamplingBsdf, DiffuseMatchesPdf) {
  check_lobe_sampling(diffuse_material(), 1000);
}

TEST(SceneSamplingBsdf, PhongMatchesPdf) {
  std::uint64_t seed = 2000;
  for (double exponent : {1.0, 10.0, 100.0}) {
    SCOPED_TRACE("exponent " + std::to_string(exponent));
    check_lobe_sampling(phong_material(exponent), seed);
    seed += 100;
  }
}

// The shading frame (which both the BSDFs and these tests use) is orthonormal with n as z, also
// at the normal -z where Duff et al.'s construction switches sign.
TEST(SceneSamplingBsdf, FrameIsOrthonormal) {
  RandomStream rng({.key = 900});
  std::vector<Vec3> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, test_normal()};
  for (int i = 0; i < 1000; ++i) {
    const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi * rng.uniform();
    const double r = std::sqrt(1.0 - z * z);
    normals.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  int bad = 0;
  for (const Vec3& n : normals) {
    const Frame f(n);
    bad += std::abs(length(f.s) - 1.0) > 1e-12 || std::abs(length(f.t) - 1.0) > 1e-12 ||
           std::abs(dot(f.s, f.t)) > 1e-12 || std::abs(dot(f.s, n)) > 1e-12 ||
           std::abs(dot(f.t, n)) > 1e-12 || length(cross(f.s, f.t) - n) > 1e-12;
  }
  EXPECT_EQ(bad, 0);
}

// The turns the azimuth tests take: every octant boundary and its neighbours on both sides
// (where the reduction switches), then random u.
std::vector<double> azimuth_test_turns() {
  RandomStream rng({.key = 901});
  std::vector<double> us = {0.0, std::nextafter(1.0, 0.0)};
  for (int k = 1; k < 64; ++k) {
    us.push_back(k / 64.0);
    us.push_back(std::nextafter(k / 64.0, 0.0));
    us.push_back(std::nextafter(k / 64.0, 1.0));
  }
  for (int i = 0; i < 100000; ++i) us.push_back(rng.uniform());
  return us;
}

// The samplers' azimuth: cos_sin_of_turn(u) against libm's cos and sin of 2πu, at the turns
// above. The bound, 8 × 2^-53 absolute, allows the series' error (1.6 × 2^-53 against long
// double, measured) and libm's: its argument 2πu is rounded first, by up to 2^-51 near a full
// turn (6.5 × 2^-53 apart at most over 2 × 10^7 random u, measured).
TEST(SceneSamplingBsdf, AzimuthMatchesLibm) {
  double worst = 0.0;
  for (const double u : azimuth_test_turns()) {
    const CosSin cs = cos_sin_of_turn(u);
    worst = std::max({worst, std::abs(cs.cos - std::cos(2.0 * kPi * u)),
                      std::abs(cs.sin - std::sin(2.0 * kPi * u))});
  }
  EXPECT_LE(worst, 8.0 * 0x1.0p-53);
}

// A round of walks computes its azimuths in SIMD lanes (cos_sin_of_turns, the widest clone the
// machine has): the scalar function's bits at every u above, the batch's length no multiple of a
// vector's so that the loop's remainder runs too; bit for bit is what keeps the walks' paths.
// Only the clone this machine selects runs here (AVX-512 on the CI machine); the others are
// checked where they are selected, by this test and by estimators.hashes.
TEST(SceneSamplingBsdf, AzimuthsInLanesAreTheScalarOnesToTheBit) {
  const std::vector<double> us = azimuth_test_turns();
  ASSERT_NE(us.size() % 16, 0U);
  std::vector<double> cos(us.size()), sin(us.size());
  cos_sin_of_turns(us, cos, sin);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < us.size(); ++i) {
    const CosSin cs = cos_sin_of_turn(us[i]);
    differ += static_cast<std::size_t>(
        std::bit_cast<std::uint64_t>(cs.cos) != std::bit_cast<std::uint64_t>(cos[i]) ||
        std::bit_cast<std::uint64_t>(cs.sin) != std::bit_cast<std::uint64_t>(sin[i]));
  }
  EXPECT_EQ(differ, 0U);
}

// Grazing Phong lobes lose much of their mass below the surface; the test above must then
// see a large invalid share (otherwise the invalid bin would test nothing).
TEST(SceneSamplingBsdf, GrazingPhongHasInvalidShare) {
  double total = 0.0;
  const std::vector<double> p =
      bin_probabilities(phong_material(10.0), test_normal(), outgoing(kOutgoing[3]), total);
  EXPECT_GT(p[kBins], 0.3);
}

TEST(SceneSamplingBsdf, DiffuseIntegratesToAlbedo) {
  // ∫ f |cos| over the whole sphere by the midpoint rule in (cos, φ): f is albedo / π on the
  // side of wo and 0 on the other, so the integral is the albedo (exact for this rule).
  const Material m = diffuse_material();
  const Vec3 wo = outgoing(kOutgoing[1]);
  constexpr int kCos = 200, kPhi = 64;
  Rgb sum;
  for (int i = 0; i < kCos; ++i) {
    const double c = -1.0 + (i + 0.5) * 2.0 / kCos;
    for (int j = 0; j < kPhi; ++j) {
      const Vec3 wi = direction_about(test_normal(), c, (j + 0.5) * 2.0 * kPi / kPhi);
      sum += bsdf_eval(m, test_normal(), wo, wi) * std::abs(c);
    }
  }
  const Rgb integral = sum * (2.0 / kCos) * (2.0 * kPi / kPhi);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(integral[c], m.albedo[c], 1e-12);
}

// Uniform direction on the sphere.
Vec3 uniform_sphere(RandomStream& rng) {
  const double z = 1.0 - 2.0 * rng.uniform();
  const double phi = 2.0 * kPi * rng.uniform();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

bool near_relative(double a, double b, double tolerance) {
  return std::abs(a - b) <= tolerance * std::max(std::abs(a), std::abs(b));
}

// f is reciprocal for both materials. The Phong pdf is symmetric in (wo, wi) (it depends on
// them through 2 (wo·n)(wi·n) - wo·wi only); the diffuse one is cos θi / π and is not, which
// is why the MIS code always asks for reverse densities with the arguments swapped.
TEST(SceneSamplingBsdf, Reciprocity) {
  RandomStream rng({.key = 3000});
  const Vec3 n = test_normal();
  for (const Material& m :
       {diffuse_material(), phong_material(1.0), phong_material(10.0), phong_material(100.0)}) {
    SCOPED_TRACE(m.name + " " + std::to_string(m.exponent));
    int f_mismatches = 0, pdf_mismatches = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 wo = uniform_sphere(rng), wi = uniform_sphere(rng);
      const Rgb f = bsdf_eval(m, n, wo, wi), f_swapped = bsdf_eval(m, n, wi, wo);
      for (int c = 0; c < 3; ++c) f_mismatches += !near_relative(f[c], f_swapped[c], 1e-9);
      const double pdf = bsdf_pdf(m, n, wo, wi);
      if (m.kind == MaterialKind::kPhong) {
        pdf_mismatches += !near_relative(pdf, bsdf_pdf(m, n, wi, wo), 1e-9);
      } else {
        const bool same_side = dot(n, wo) * dot(n, wi) > 0.0;
        pdf_mismatches += !near_relative(pdf, same_side ? std::abs(dot(n, wi)) / kPi : 0.0, 1e-12);
      }
    }
    EXPECT_EQ(f_mismatches, 0);
    EXPECT_EQ(pdf_mismatches, 0);
  }
}

TEST(SceneSamplingBsdf, MirrorCarriesAlbedo) {
  const Material m{"mirror", MaterialKind::kMirror, {0.9, 0.5, 0.2}, 0.0};
  const Vec3 n = test_normal();
  for (const Outgoing& o : kOutgoing) {
    SCOPED_TRACE(o.name);
    const Vec3 wo = outgoing(o);
    const BsdfSample s = bsdf_sample(m, n, wo, 0.3, 0.6);
    ASSERT_TRUE(s.valid);
    EXPECT_TRUE(s.delta);
    const Vec3 expected = reflect(wo, facing(n, wo));
    EXPECT_NEAR(length(s.wi - expected), 0.0, 1e-15);
    const Rgb carried = s.f * (std::abs(dot(s.wi, n)) / s.pdf);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(carried[c], m.albedo[c], 1e-12 * m.albedo[c]);
    // A delta is never hit by chance.
    EXPECT_TRUE(bsdf_eval(m, n, wo, s.wi).is_black());
    EXPECT_EQ(bsdf_pdf(m, n, wo, s.wi), 0.0);
  }
  EXPECT_TRUE(is_delta(m));
  EXPECT_FALSE(is_delta(diffuse_material()));
  EXPECT_FALSE(is_delta(phong_material(10.0)));
}

// ---------------------------------------------------------------------------------------------
// Emitters

constexpr int kEmitterSamples = 200000;
constexpr int kBarySteps = 8;  // each triangle cut into kBarySteps² equal sub-triangles

// Barycentric coordinates (b1, b2) of p with respect to p1 and p2 of triangle t.
std::pair<double, double> barycentric(const Triangle& t, const Vec3& p) {
  const Vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, d = p - t.p0;
  const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
  const double d1 = dot(d, e1), d2 = dot(d, e2);
  const double det = d11 * d22 - d12 * d12;
  return {(d22 * d1 - d12 * d2) / det, (d11 * d2 - d12 * d1) / det};
}

// The sub-triangle of (b1, b2): the grid cell (i, j) and which of its halves; cells past the
// hypotenuse do not exist (probability 0 in the test).
int sub_triangle(double b1, double b2) {
  const double x = b1 * kBarySteps, y = b2 * kBarySteps;
  const int i = std::clamp(static_cast<int>(x), 0, kBarySteps - 1);
  const int j = std::clamp(static_cast<int>(y), 0, kBarySteps - 1);
  const int upper = (x - i) + (y - j) >= 1.0 ? 1 : 0;
  return (i * kBarySteps + j) * 2 + upper;
}

bool sub_triangle_exists(int index) {
  const int upper = index % 2, cell = index / 2;
  const int i = cell / kBarySteps, j = cell % kBarySteps;
  return i + j + upper <= kBarySteps - 1;
}

// Each emitter's share of the total power: π·area·mean radiance (one-sided) or 4π·mean
// intensity; indices as the emitter points report them.
struct PowerShares {
  std::vector<double> triangle, point;
};
PowerShares power_shares(const SceneDescription& d) {
  PowerShares p{std::vector<double>(d.triangles.size(), 0.0),
                std::vector<double>(d.point_lights.size(), 0.0)};
  double total = 0.0;
  for (std::size_t i = 0; i < d.triangles.size(); ++i) {
    p.triangle[i] = kPi * triangle_area(d.triangles[i]) * d.triangles[i].emission.average();
    total += p.triangle[i];
  }
  for (std::size_t i = 0; i < d.point_lights.size(); ++i) {
    p.point[i] = 4.0 * kPi * d.point_lights[i].intensity.average();
    total += p.point[i];
  }
  for (double& v : p.triangle) v /= total;
  for (double& v : p.point) v /= total;
  return p;
}

TEST(SceneSamplingEmitters, CornellLightIsSampledByPowerAndUniformly) {
  const Scene scene(*built_in_scene("cornell"));
  const SceneDescription& d = scene.description();
  const PowerShares shares = power_shares(d);
  // The light quad: the triangles with emission (two, equal), of total area 0.2 × 0.2.
  double light_area = 0.0;
  int emitting = 0;
  for (const Triangle& t : d.triangles) {
    if (!t.emission.is_black()) {
      light_area += triangle_area(t);
      ++emitting;
    }
  }
  ASSERT_EQ(emitting, 2);
  EXPECT_NEAR(light_area, 0.04, 1e-12);
  for (std::uint32_t i = 0; i < d.triangles.size(); ++i) {
    const double expected = d.triangles[i].emission.is_black() ? 0.0 : 1.0 / light_area;
    EXPECT_NEAR(scene.emitters().pdf_area(i), expected, 1e-12 * expected) << "triangle " << i;
  }

  const std::size_t cells = 2 * kBarySteps * kBarySteps;
  std::vector<double> triangle_counts(d.triangles.size(), 0.0);
  std::vector<double> cell_counts(d.triangles.size() * cells, 0.0);
  std::vector<double> cell_p(d.triangles.size() * cells, 0.0);
  for (std::size_t t = 0; t < d.triangles.size(); ++t) {
    for (std::size_t c = 0; c < cells; ++c) {
      if (sub_triangle_exists(static_cast<int>(c))) {
        cell_p[t * cells + c] = shares.triangle[t] / (kBarySteps * kBarySteps);
      }
    }
  }
  RandomStream rng({.key = 4000});
  int off_triangle = 0, wrong_fields = 0;
  for (int n = 0; n < kEmitterSamples; ++n) {
    const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    const EmitterPoint e = scene.emitters().sample(u0, u1, u2);
    ASSERT_FALSE(e.point_light);
    ASSERT_LT(e.index, d.triangles.size());
    const Triangle& t = d.triangles[e.index];
    triangle_counts[e.index] += 1.0;
    const auto [b1, b2] = barycentric(t, e.position);
    off_triangle += b1 < -1e-12 || b2 < -1e-12 || b1 + b2 > 1.0 + 1e-12 ||
                    std::abs(dot(e.position - t.p0, triangle_normal(t))) > 1e-12;
    cell_counts[e.index * cells + sub_triangle(b1, b2)] += 1.0;
    wrong_fields += !near_relative(e.pdf_area, 1.0 / light_area, 1e-12) ||
                    !(e.radiance == t.emission) || length(e.normal - triangle_normal(t)) > 1e-15;
  }
  EXPECT_EQ(off_triangle, 0);
  EXPECT_EQ(wrong_fields, 0);
  EXPECT_GT(chi_square_p_value(triangle_counts, shares.triangle), kMinP);
  EXPECT_GT(chi_square_p_value(cell_counts, cell_p), kMinP);
}

// One emitting quad and one point light: the choice follows π·area·radiance against
// 4π·intensity (both averaged over the channels).
TEST(SceneSamplingEmitters, PointLightAndQuadByPower) {
  SceneDescription d;
  d.name = "quad-and-point";
  d.materials.push_back(diffuse_material());
  const Rgb radiance{3.0, 2.0, 1.0};  // power π · 2 · 2, 2π per triangle
  d.triangles.push_back({{0, 0, 0}, {0, 0, 1}, {2, 0, 1}, 0, radiance});
  d.triangles.push_back({{0, 0, 0}, {2, 0, 1}, {2, 0, 0}, 0, radiance});
  d.point_lights.push_back({{1.0, 1.0, 0.5}, {1.0, 0.5, 0.3}});  // power 4π · 0.6
  d.camera = {{1.0, 2.0, 3.0}, {1.0, 0.0, 0.5}, {0.0, 1.0, 0.0}, 45.0};
  const Scene scene(d);
  const PowerShares shares = power_shares(scene.description());
  ASSERT_NEAR(shares.triangle[0], 2.0 / 6.4, 1e-12);
  ASSERT_NEAR(shares.point[0], 2.4 / 6.4, 1e-12);
  EXPECT_TRUE(scene.emitters().has_point_lights());
  for (std::uint32_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(scene.emitters().pdf_area(i), shares.triangle[i] / 1.0, 1e-12);  // area 1 each
  }

  std::vector<double> counts(3, 0.0);
  RandomStream rng({.key = 5000});
  int wrong_fields = 0;
  for (int n = 0; n < kEmitterSamples; ++n) {
    const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    const EmitterPoint e = scene.emitters().sample(u0, u1, u2);
    if (e.point_light) {
      counts[2] += 1.0;
      wrong_fields += e.index != 0 || !(e.position == d.point_lights[0].position) ||
                      !(e.radiance == d.point_lights[0].intensity) ||
                      !near_relative(e.pdf_area, shares.point[0], 1e-12);
    } else {
      counts[e.index] += 1.0;
      wrong_fields += e.index > 1 || !near_relative(e.pdf_area, shares.triangle[e.index], 1e-12);
    }
  }
  EXPECT_EQ(wrong_fields, 0);
  EXPECT_GT(chi_square_p_value(counts, {shares.triangle[0], shares.triangle[1], shares.point[0]}),
            kMinP);
}

// The emitters are chosen in proportion to their power: the alias table's probabilities are the
// entries' own to rounding, and entry_for picks by the table (over a fine grid of u, the entries'
// shares are the table's to within the grid's spacing at each piece of a bucket), on
// every built-in scene and on one whose powers are very uneven (one bright quad and 400 faint
// slivers, so that most buckets borrow from the quad).
TEST(SceneSamplingEmitters, AliasChoiceIsThePowerDistribution) {
  std::vector<SceneDescription> scenes;
  for (const std::string& name : built_in_scene_names()) scenes.push_back(*built_in_scene(name));
  SceneDescription uneven;
  uneven.name = "uneven";
  uneven.materials.push_back(diffuse_material());
  for (int i = 0; i < 400; ++i) {
    const double x = 0.01 * i;
    uneven.triangles.push_back(
        {{x, 0, 0}, {x, 0, 1}, {x + 0.001 * (1 + i % 7), 0, 1}, 0, Rgb{1e-3, 1e-3, 1e-3}});
  }
  uneven.triangles.push_back({{0, 1, 0}, {0, 1, 4}, {4, 1, 4}, 0, Rgb{50.0, 50.0, 50.0}});
  uneven.camera = {{1.0, 2.0, 3.0}, {1.0, 0.0, 0.5}, {0.0, 1.0, 0.0}, 45.0};
  scenes.push_back(uneven);
  for (const SceneDescription& d : scenes) {
    const Scene scene(d);
    const Emitters& emitters = scene.emitters();
    if (emitters.empty()) continue;
    const std::vector<double> want = emitters.probabilities();
    const std::vector<double> table = emitters.choice_probabilities();
    ASSERT_EQ(table.size(), want.size()) << d.name;
    for (std::size_t i = 0; i < want.size(); ++i) {
      EXPECT_NEAR(table[i], want[i], 1e-14) << d.name << " entry " << i;
    }
    constexpr std::size_t kGrid = 1 << 20;
    std::vector<std::size_t> count(want.size(), 0);
    for (std::size_t k = 0; k < kGrid; ++k) ++count[emitters.entry_for((k + 0.5) / kGrid)];
    // Each bucket is two pieces (its entry's and its alias's), and a piece's share of the grid
    // differs from its length by at most a grid step: the shares' total distance from the
    // table's is at most two steps a bucket.
    const double step = 1.0 / kGrid;
    double distance = 0.0;
    for (std::size_t i = 0; i < want.size(); ++i) {
      distance += std::abs(static_cast<double>(count[i]) * step - table[i]);
    }
    EXPECT_LE(distance, 2.0 * static_cast<double>(want.size()) * step) << d.name;
  }
}

// A batch of points is sample()'s points one by one, to the bit, on every built-in scene and on
// cornell with two point lights added, for a batch of every size up to the capacity.
TEST(SceneSamplingEmitters, SampleManyIsSampleOneByOne) {
  std::vector<SceneDescription> scenes;
  for (const std::string& name : built_in_scene_names()) scenes.push_back(*built_in_scene(name));
  SceneDescription lit = *built_in_scene("cornell");
  lit.name = "cornell with point lights";
  lit.point_lights.push_back({{0.1, 0.5, -0.2}, Rgb{2.0, 1.0, 0.5}});
  lit.point_lights.push_back({{-0.0, 0.2, 0.4}, Rgb{0.5, 0.5, 3.0}});  // -0 + 0 would be +0
  scenes.push_back(lit);
  for (const SceneDescription& d : scenes) {
    const std::string& name = d.name;
    const Scene scene(d);
    const Emitters& emitters = scene.emitters();
    if (emitters.empty()) continue;
    RandomStream rng({.key = 11, .purpose = StreamPurpose::kCameraPath});
    for (std::size_t n = 1; n <= EmitterPoints::kCapacity; ++n) {
      std::vector<double> u(3 * n);
      rng.uniforms(u);
      EmitterPoints many;
      emitters.sample_many(u, many);
      ASSERT_EQ(many.size, n);
      for (std::size_t j = 0; j < n; ++j) {
        const EmitterPoint want = emitters.sample(u[3 * j], u[3 * j + 1], u[3 * j + 2]);
        const EmitterPoint got = many[j];
        EXPECT_EQ(std::memcmp(&got.position, &want.position, sizeof(Vec3)), 0) << name << " " << j;
        EXPECT_EQ(std::memcmp(&got.normal, &want.normal, sizeof(Vec3)), 0) << name << " " << j;
        EXPECT_EQ(std::memcmp(&got.radiance, &want.radiance, sizeof(Rgb)), 0) << name << " " << j;
        EXPECT_EQ(got.pdf_area, want.pdf_area) << name << " " << j;
        EXPECT_EQ(got.point_light, want.point_light) << name << " " << j;
        EXPECT_EQ(got.index, want.index) << name << " " << j;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Camera

// A camera whose up vector is not orthogonal to its view, on a non-square film.
const Camera kTiltedCamera{{1.0, 2.0, 3.0}, {-1.0, 0.5, 0.0}, {0.2, 1.0, 0.1}, 50.0};
constexpr std::uint32_t kFilmWidth = 8, kFilmHeight = 6;

TEST(SceneSamplingCamera, ProjectFindsThePixel) {
  const CameraModel camera(kTiltedCamera, kFilmWidth, kFilmHeight);
  const Vec3 forward = normalize(kTiltedCamera.look_at - kTiltedCamera.position);
  const double offsets[] = {1e-6, 0.25, 0.5, 0.75, 1.0 - 1e-6};
  int wrong = 0;
  for (std::uint32_t x = 0; x < kFilmWidth; ++x) {
    for (std::uint32_t y = 0; y < kFilmHeight; ++y) {
      for (double ox : offsets) {
        for (double oy : offsets) {
          const Vec3 d = camera.direction(x + ox, y + oy);
          const auto pixel = camera.project(d);
          wrong += !pixel || pixel->x != x || pixel->y != y ||
                   std::abs(pixel->cos_theta - dot(d, forward)) > 1e-14;
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0);
}

// Solid angle of the spherical triangle of unit vectors a, b, c (Van Oosterom and Strackee).
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 2.0 * std::atan2(std::abs(dot(a, cross(b, c))), 1.0 + dot(a, b) + dot(b, c) + dot(c, a));
}

TEST(SceneSamplingCamera, PixelPdfIntegratesToOne) {
  const CameraModel camera(kTiltedCamera, kFilmWidth, kFilmHeight);
  constexpr int kSteps = 64;
  const std::pair<std::uint32_t, std::uint32_t> pixels[] = {
      {0, 0}, {kFilmWidth / 2, kFilmHeight / 2}, {kFilmWidth - 1, kFilmHeight - 1}, {6, 1}};
  for (const auto& [px, py] : pixels) {
    SCOPED_TRACE("pixel " + std::to_string(px) + "," + std::to_string(py));
    double pdf_integral = 0.0, importance_integral = 0.0;
    const double h = 1.0 / kSteps;
    for (int i = 0; i < kSteps; ++i) {
      for (int j = 0; j < kSteps; ++j) {
        const double fx = px + i * h, fy = py + j * h;
        const Vec3 d00 = camera.direction(fx, fy), d10 = camera.direction(fx + h, fy);
        const Vec3 d01 = camera.direction(fx, fy + h), d11 = camera.direction(fx + h, fy + h);
        const double omega = solid_angle(d00, d10, d11) + solid_angle(d00, d11, d01);
        const auto centre = camera.project(camera.direction(fx + 0.5 * h, fy + 0.5 * h));
        ASSERT_TRUE(centre);
        pdf_integral += camera.pixel_pdf(centre->cos_theta) * omega;
        importance_integral += camera.importance(centre->cos_theta) * centre->cos_theta * omega;
      }
    }
    EXPECT_NEAR(pdf_integral, 1.0, 1e-5);
    // A camera ray carries W cos / p = 1, and the pixel measures ∫ W cos dω = 1.
    EXPECT_NEAR(importance_integral, 1.0, 1e-5);
  }
}

TEST(SceneSamplingCamera, OutsideTheFieldOfViewProjectsToNothing) {
  const CameraModel camera(kTiltedCamera, kFilmWidth, kFilmHeight);
  const Vec3 forward = normalize(kTiltedCamera.look_at - kTiltedCamera.position);
  const double w = kFilmWidth, h = kFilmHeight;
  for (const auto& [fx, fy] :
       {std::pair{-0.01, 0.5 * h}, std::pair{w + 0.01, 0.5 * h}, std::pair{0.5 * w, -0.01},
        std::pair{0.5 * w, h + 0.01}, std::pair{-3.0 * w, 4.0 * h}}) {
    EXPECT_FALSE(camera.project(camera.direction(fx, fy))) << fx << "," << fy;
  }
  EXPECT_FALSE(camera.project(-forward));
  EXPECT_FALSE(camera.project(normalize(cross(forward, kTiltedCamera.up))));  // sideways
  EXPECT_TRUE(camera.project(forward));
}

}  // namespace
}  // namespace pcbench::scene
