// Small vector types for scenes: points and directions (Vec3) and RGB values (Rgb), in double.
// Embree gets float copies of the geometry; all shading and path arithmetic stays in double so
// that pdf ratios in the MIS weights do not lose precision on long paths.
#pragma once

#include <algorithm>
#include <cmath>

namespace pcbench::scene {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator*(double s, const Vec3& v) {
  return v * s;
}
constexpr double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& v) {
  return std::sqrt(dot(v, v));
}
inline Vec3 normalize(const Vec3& v) {
  return v / length(v);
}
inline bool is_finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
// The mirror image of direction `v` (pointing away from the surface) about normal `n`.
inline Vec3 reflect(const Vec3& v, const Vec3& n) {
  return 2.0 * dot(v, n) * n - v;
}

struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;

  constexpr double operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
  constexpr Rgb operator-(const Rgb& o) const { return {r - o.r, g - o.g, b - o.b}; }
  constexpr Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
  constexpr Rgb operator*(double s) const { return {r * s, g * s, b * s}; }
  constexpr Rgb operator/(double s) const { return {r / s, g / s, b / s}; }
  Rgb& operator+=(const Rgb& o) {
    r += o.r;
    g += o.g;
    b += o.b;
    return *this;
  }
  constexpr bool operator==(const Rgb&) const = default;

  constexpr bool is_black() const { return r == 0.0 && g == 0.0 && b == 0.0; }
  constexpr double max_channel() const { return std::max(r, std::max(g, b)); }
  constexpr double average() const { return (r + g + b) / 3.0; }
};

constexpr Rgb operator*(double s, const Rgb& c) {
  return c * s;
}

// An orthonormal frame around a unit normal (Duff et al., "Building an orthonormal basis,
// revisited", JCGT 2017): local z is the normal.
struct Frame {
  Vec3 s, t, n;

  explicit Frame(const Vec3& normal) : n(normal) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
  }
  Vec3 to_world(const Vec3& local) const { return local.x * s + local.y * t + local.z * n; }
  Vec3 to_local(const Vec3& world) const { return {dot(world, s), dot(world, t), dot(world, n)}; }
};

inline constexpr double kPi = 3.14159265358979323846;
// Multiplied by instead of dividing by π: a division costs several multiplications.
inline constexpr double kInvPi = 1.0 / kPi;

}  // namespace pcbench::scene
