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

}  // namespace pcbench::scene
