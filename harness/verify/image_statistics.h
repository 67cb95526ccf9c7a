// Statistics of a scene's R independent replicate images: per-pixel mean and standard error, z
// maps and their summary. The tests that decide whether two sets of images agree are over blocks
// of pixels (harness/verify/block_pyramid.h); as for runs (statistics.h), every standard error is
// the spread across replicates.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "results/image.h"

namespace pcbench {

// Throws std::invalid_argument unless `image` holds width × height × 3 values and has the size
// of `first`.
void check_image(const Image& image, const Image& first);
// Throws std::invalid_argument for fewer than 2 images, or one not the size of `like` (or, without
// it, of the first).
void check_replicates(std::span<const Image> images, const Image* like = nullptr);

struct PixelStatistics {
  Image mean;
  Image standard_error;  // sample sd across replicates / sqrt(R)
  std::uint32_t replicates = 0;
};

// Throws std::invalid_argument for fewer than 2 replicates or images of different sizes.
PixelStatistics pixel_statistics(std::span<const Image> replicates);

// Relative errors against a reference image divide by the reference plus this share of its mean,
// so that black pixels do not dominate a relative MSE.
inline constexpr double kRelativeErrorFloor = 1e-2;
// That denominator for every value of `reference`.
std::vector<double> relative_error_scale(const Image& reference);
// The relative variance of an image with these standard errors: the mean over pixels and
// channels of se² / (mean + floor)², what it adds to every relative MSE measured against it (a
// cached reference's quality; what image errors subtract for a Monte Carlo reference).
double relative_variance(const Image& mean, const Image& standard_error);

// z = (mean_a - mean_b) / sqrt(se_a² + se_b²) per pixel and channel. Where the denominator is 0,
// z is 0 for equal means and ±inf otherwise (never the NaN of 0/0); NaN only from NaN input.
// Throws std::invalid_argument for images of different sizes.
Image z_map(const PixelStatistics& a, const PixelStatistics& b);
Image z_map(const PixelStatistics& a, const Image& exact);  // the exact image has se 0

// Pixel-level guards, as in the verification of analytic runs. `b` holds the other estimator's
// replicates, or just the exact image.
struct PixelTestSummary {
  double max_abs_z = 0;                     // NaN if some z is NaN
  std::uint32_t pixels_beyond_4_sigma = 0;  // pixels with |z| > 4 in some channel
  // Pixels where one side's replicates are all 0 in some channel and the other side's are not:
  // there the estimator may never sample the pixel, and its z says nothing.
  std::uint32_t low_count_pixels = 0;
  // An upper bound on the expected pixels_beyond_4_sigma when the means agree: pixels x 3 x
  // P(|T| > 4) with T Student's t of the smaller side's R - 1 dof (Welch's dof is at least that,
  // and fewer dof only fatten the tails; the union bound holds whatever the channels'
  // correlation). Normal tails would be far too optimistic at small R: 6e-5 against 5e-3 at R = 8.
  double expected_beyond_4_sigma = 0;
};
// Throws std::invalid_argument for images of different sizes, fewer than 2 replicates in a, or
// a b that is neither one exact image nor at least 2 replicates.
PixelTestSummary summarize_z(const Image& z, std::span<const Image> a, std::span<const Image> b);

}  // namespace pcbench
