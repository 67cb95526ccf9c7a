// The pinhole camera as a sampling technique: pixel rays, the projection of a point back to its
// pixel (for light tracing, t = 1), and the densities the MIS weights need.
//
// Pixel j measures I_j = ∫ W_j(ω) L(ω) cos θ dω with a box filter: W_j = 1 / (A_pix cos⁴ θ) on
// the directions through pixel j, where A_pix is a pixel's area on the image plane at distance 1.
// Sampling ω uniformly over the pixel's area has density p(ω) = 1 / (A_pix cos³ θ), so a camera
// ray carries W_j cos θ / p = 1.
#pragma once

#include <cstdint>
#include <optional>

#include "integrands/scenes/scene_description.h"
#include "integrands/scenes/scene_math.h"

namespace pcbench::scene {

struct PixelPosition {
  std::uint32_t x = 0, y = 0;  // the pixel (top row y = 0)
  double cos_theta = 0.0;      // cosine between the direction and the view axis
};

class CameraModel {
 public:
  CameraModel(const Camera& camera, std::uint32_t width, std::uint32_t height);

  const Vec3& position() const { return position_; }
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }

  // Unit direction through film position (fx, fy) in pixel units: [0, W) × [0, H).
  Vec3 direction(double fx, double fy) const;

  // The pixel a direction from the camera goes through, if any.
  std::optional<PixelPosition> project(const Vec3& direction) const {
    const FilmPoint p = film_point(direction);
    if (!p.on_film) return std::nullopt;
    return PixelPosition{static_cast<std::uint32_t>(p.fx), static_cast<std::uint32_t>(p.fy),
                         p.cos_theta};
  }

  // project()'s arithmetic, branch-free for a loop meant to run in SIMD lanes (light tracing's
  // connections, connection_lanes.cpp): where `direction` meets the film, in film units
  // ([0, W) × [0, H) when on_film), and its cosine to the view axis. Off the film (or behind the
  // camera) fx and fy mean nothing.
  struct FilmPoint {
    double fx, fy, cos_theta;
    bool on_film;
  };
  [[gnu::always_inline]] FilmPoint film_point(const Vec3& direction) const {
    const double cos_theta = dot(direction, forward_);
    // One division: the point on the image plane at distance 1 is direction / cos_theta.
    const double to_plane = 1.0 / cos_theta;
    const double fx = 0.5 * width_ + dot(direction, right_) * to_plane * film_per_plane_x_;
    const double fy = 0.5 * height_ - dot(direction, up_) * to_plane * film_per_plane_y_;
    const bool on_film =
        (cos_theta > 0.0) & (fx >= 0.0) & (fx < width_) & (fy >= 0.0) & (fy < height_);
    return {fx, fy, cos_theta, on_film};
  }

  // Cosine between a unit direction and the view axis.
  double cos_theta(const Vec3& direction) const { return dot(direction, forward_); }

  // Solid-angle density of a pixel's ray sampling at a direction with this cosine.
  double pixel_pdf(double cos_theta) const {
    return 1.0 / (pixel_area_ * cos_theta * cos_theta * cos_theta);
  }
  // W_j for a direction through pixel j.
  double importance(double cos_theta) const { return pixel_pdf(cos_theta) / cos_theta; }

 private:
  Vec3 position_, forward_, right_, up_;
  double half_width_ = 0.0, half_height_ = 0.0;  // of the image plane at distance 1
  // Image plane coordinates to film ones: W / (2 half_width), H / (2 half_height).
  double film_per_plane_x_ = 0.0, film_per_plane_y_ = 0.0;
  double pixel_area_ = 0.0;
  std::uint32_t width_ = 0, height_ = 0;
};

}  // namespace pcbench::scene
