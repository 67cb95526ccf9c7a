#include "integrands/scenes/camera_model.h"

#include <cmath>

namespace pcbench::scene {

CameraModel::CameraModel(const Camera& camera, std::uint32_t width, std::uint32_t height)
    : position_(camera.position), width_(width), height_(height) {
  forward_ = normalize(camera.look_at - camera.position);
  right_ = normalize(cross(forward_, camera.up));
  up_ = cross(right_, forward_);
  half_height_ = std::tan(camera.fov_degrees * kPi / 360.0);
  half_width_ = half_height_ * static_cast<double>(width) / static_cast<double>(height);
  pixel_area_ = (2.0 * half_width_ / width) * (2.0 * half_height_ / height);
  film_per_plane_x_ = 0.5 * width / half_width_;
  film_per_plane_y_ = 0.5 * height / half_height_;
}

Vec3 CameraModel::direction(double fx, double fy) const {
  const double x = (2.0 * fx / width_ - 1.0) * half_width_;
  const double y = (1.0 - 2.0 * fy / height_) * half_height_;
  return normalize(forward_ + x * right_ + y * up_);
}

std::optional<PixelPosition> CameraModel::project(const Vec3& direction) const {
  const double cos_theta = dot(direction, forward_);
  if (cos_theta <= 0.0) return std::nullopt;
  // One division: the point on the image plane at distance 1 is direction / cos_theta.
  const double to_plane = 1.0 / cos_theta;
  const double fx = 0.5 * width_ + dot(direction, right_) * to_plane * film_per_plane_x_;
  const double fy = 0.5 * height_ - dot(direction, up_) * to_plane * film_per_plane_y_;
  if (!(fx >= 0.0 && fx < width_ && fy >= 0.0 && fy < height_)) return std::nullopt;
  return PixelPosition{static_cast<std::uint32_t>(fx), static_cast<std::uint32_t>(fy), cos_theta};
}

}  // namespace pcbench::scene
