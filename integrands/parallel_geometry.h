// Geometry shared by the transport-like integrands (form-factor, linear-emitter, blocker, door,
// door-2d): a light point x on a unit segment (flatland) or unit square at z = 0, a camera point
// y on a parallel one at z = h, and a wall or strip on the plane z = t h in between (0 < t < 1).
//
// Kernels (the form factor's integrand, cos θ_x cos θ_y over the distance term, with
// cos θ_x = cos θ_y = h / r; Siegel & Howell, "Thermal Radiation Heat Transfer"):
//   flatland (1+1):  k(u) = h² / (2 r³),        r² = h² + u²,       u = y0 - x0
//   3D (2+2):        k(u) = h² / (π r⁴),        r² = h² + |u|²,     u = y - x
// The segment x -> y crosses the plane z = t h at c = x + t (y - x), one axis at a time, so an
// axis-aligned opening or strip on that plane separates into one condition per axis.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "base/params.h"

namespace pcbench::parallel {

// `distance`: h, from the light plane to the camera plane (default 1, range [0.01, 100]).
ParamSpec distance_param();

// A height on the plane between, as a fraction t of the distance (range [0.01, 0.99]).
ParamSpec height_param(std::string name, std::string description);

// A length or position on the plane between (default_value, range [min, max]).
ParamSpec length_param(std::string name, std::string description, std::string default_value,
                       double min, double max);

inline double flatland_kernel(double u, double h) {
  const double r2 = h * h + u * u;
  return h * h / (2.0 * r2 * std::sqrt(r2));
}

inline double kernel_3d(double u0, double u1, double h) {
  const double r2 = h * h + u0 * u0 + u1 * u1;
  return h * h / (M_PI * r2 * r2);
}

// Where the segment from x to y (one axis) crosses the plane at fraction t of the distance.
inline double crossing(double x, double y, double t) {
  return x + t * (y - x);
}

// Flatland (1 + 1 dimensions) with an interval [lo, hi] of the line z = t h between the segments:
// what door (light passes only through the interval) and blocker (the interval stops it) share.
// The unoccluded kernel is their resampling importance: it cannot see the interval.
class FlatlandInterval {
 public:
  FlatlandInterval(double distance, double height, double lo, double hi)
      : distance_(distance), height_(height), lo_(lo), hi_(hi) {}
  int light_dims() const { return 1; }
  int camera_dims() const { return 1; }
  double approximate_importance(const double* x, const double* y) const {
    return flatland_kernel(y[0] - x[0], distance_);
  }

 protected:
  // Whether the segment x -> y crosses the line z = t h inside [lo, hi].
  bool crosses_interval(const double* x, const double* y) const {
    const double c = crossing(x[0], y[0], height_);
    return c >= lo_ && c <= hi_;
  }
  // ∫∫ k 1[the crossing is in [lo, hi]] (closed form).
  double through_interval() const;

  double distance_;
  double height_;  // t
  double lo_, hi_;
};

// For a light coordinate x in [0, 1]: the offsets u = y - x with y in [0, 1] whose crossing lies
// in [lo, hi], as [u_lo, u_hi] (empty when u_lo >= u_hi). Each bound is the larger (smaller) of
// two affine functions of x.
struct OffsetRange {
  double lo, hi;
};
inline OffsetRange offsets_through(double x, double t, double lo, double hi) {
  return {std::fmax(-x, (lo - x) / t), std::fmin(1.0 - x, (hi - x) / t)};
}

// The x in (0, 1) where offsets_through changes form (a bound switches between its two affine
// functions, or the range empties): every kink of an integral over the range, as a function of x.
std::vector<double> offset_kinks(double t, double lo, double hi);

// ∫_0^1 ∫_0^1 k(y0 - x0) dy0 dx0 = √(1 + h²) - h: Hottel's crossed strings (crossed minus
// uncrossed, halved) for two directly opposed unit segments.
double flatland_total(double h);

// ∫_0^1 ∫_0^1 k(y0 - x0) 1[lo <= c <= hi] dy0 dx0 in closed form. For fixed x0 the inner
// integral is H(u_hi) - H(u_lo) with the antiderivative H(u) = u / (2 √(h² + u²)); between the
// kinks both bounds are affine in x0 (slope -1/t or -1), and ∫ H(α x + β) dx = √(h² + u²) / (2α).
double flatland_through(double h, double t, double lo, double hi);

// Form factor between two directly opposed parallel unit squares at distance h, equal to
// ∫∫ k(y - x) dy dx over both squares (Howell's catalog, configuration C-11, with X = Y = 1/h):
//   F = 2/(π X Y) [ ½ ln((1+X²)(1+Y²)/(1+X²+Y²)) + X √(1+Y²) atan(X/√(1+Y²))
//                   + Y √(1+X²) atan(Y/√(1+X²)) - X atan X - Y atan Y ].
double square_form_factor(double h);

// ∫_0^a ∫_0^b k(u0, u1) du1 du0 (signed: odd in a and in b): the form factor from a point to a
// parallel rectangle with one corner above it (Howell's catalog, configuration B-3):
//   (1/2π) [ A/√(1+A²) atan(B/√(1+A²)) + B/√(1+B²) atan(A/√(1+B²)) ],  A = a/h, B = b/h.
double corner_integral(double a, double b, double h);

// ∫ k over the rectangle [a0, a1] × [b0, b1] of offsets (0 if empty).
double rectangle_integral(double a0, double a1, double b0, double b1, double h);

}  // namespace pcbench::parallel
