// Statistics of a scene's R independent replicate images: per-pixel mean and standard error, z
// maps, and the tile tests that verify a scene estimator against another or against an exact
// image.
//
// Why tiles: one test per pixel would need R large enough for every pixel's mean to be normal and
// a Holm correction over millions of tests, which leaves no power. The mean of a tile of 8x8
// pixels averages 64 pixels per replicate, so its R replicate values are close to normal, and a
// bias confined to a small region still moves its tile's mean. As for runs (statistics.h), every
// standard error is the spread across replicates.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "results/image.h"

namespace pcbench {

// A bright tile's minimum detectable bias should be at most this share of its mean for a passing
// comparison to say something (the scene counterpart of a run's detectable relative bias).
inline constexpr double kMaxBrightRelativeMdb = 0.05;

// How many times both runs' samples per pixel would bring a tile comparison's largest relative
// detectable bias down to kMaxBrightRelativeMdb at the same replicate count: (mdb / 0.05)², as
// the detectable bias goes with the standard errors, hence with 1/sqrt(samples per pixel) (the
// t quantiles depend on the replicate count only). Below 1: the requirement is met already.
inline double tile_samples_factor(double relative_mdb) {
  const double r = relative_mdb / kMaxBrightRelativeMdb;
  return r * r;
}

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

struct TileOptions {
  std::uint32_t tile = 8;  // edge length in pixels; edge tiles may be smaller
  double bright_fraction = 0.1;
  double power = 0.8;  // of the minimum detectable bias
  // How many tested verdicts the comparison is decided with, itself included: a session adjusts
  // the comparison's p-value again with Holm over its whole family (statistics.h,
  // decide_family). The detectable bias is computed at the threshold that then decides, the
  // Bonferroni share alpha / (family_size × tests): Holm's first step at both levels (its later
  // steps are less strict, so the figure is conservative, never optimistic). 1 for a comparison
  // decided alone.
  std::uint32_t family_size = 1;
};

struct TileTest {
  std::uint32_t tile_x = 0, tile_y = 0, channel = 0;
  double mean_a = 0, mean_b = 0;  // tile means (b: the other estimator or the exact tile mean)
  double statistic = 0, dof = 0, p_value = 1, p_adjusted = 1;
  // Tile mean (average of a and b) > 0 and >= bright_fraction x the image mean of the channel.
  bool bright = false;
  // Absolute, at `power`, for a two-sided test at the Bonferroni share
  // alpha / (family_size × tests), with the Student quantiles of the tile test's dof.
  double min_detectable_bias = 0;
};

struct TileTestResult {
  std::vector<TileTest> tiles;  // row of tiles by row, then channel within a tile
  std::uint32_t tests = 0;      // every tile x 3 channels
  double min_p_adjusted = 1;    // Holm over all tile/channel tests
  bool rejected = false;        // min_p_adjusted <= alpha (the comparison decided alone)
  // The share of alpha each tile's raw p-value is held to for the power statement:
  // alpha / (family_size × tests).
  double detection_share = 0;
  // Max over bright tiles of min_detectable_bias / tile mean; compare with
  // kMaxBrightRelativeMdb. NaN if some bright tile's is NaN, 0 without bright tiles.
  double worst_bright_relative_mdb = 0;
  std::uint32_t bright_tiles = 0;
};

// Per tile and channel, each replicate's tile mean is one observation; the R_a observations of a
// against the R_b of b give Welch's two-sample test. A tile with zero variance on both sides is
// tested exactly (p = 1 for equal means, 0 otherwise). A tile holding a non-finite value gets
// p = 0: a NaN or inf pixel is a defect that must not pass. Throws std::invalid_argument for
// fewer than 2 replicates on a side, images of different sizes, an empty image, alpha outside
// (0, 1), tile 0, power outside (0, 1), or family_size 0.
TileTestResult compare_tiles(std::span<const Image> a, std::span<const Image> b, double alpha,
                             const TileOptions& options = {});

// The same against an exact image: a one-sample t test (dof R - 1) of the replicate tile means
// against the exact tile mean.
TileTestResult test_tiles_against_exact(std::span<const Image> a, const Image& exact, double alpha,
                                        const TileOptions& options = {});

// The same against a converged reference image with its own per-pixel standard error (another
// renderer's reference): Welch's test of the replicate tile means against the reference tile
// mean, whose variance is the sum of its pixels' se² over the tile's pixel count squared
// (pixels taken as independent) with infinite dof. Where every se is 0 this is
// test_tiles_against_exact. Throws as test_tiles_against_exact, and for a stderr image of another
// size.
TileTestResult test_tiles_against_reference(std::span<const Image> a, const Image& reference,
                                            const Image& reference_stderr, double alpha,
                                            const TileOptions& options = {});

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
