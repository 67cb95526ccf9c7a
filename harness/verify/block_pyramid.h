// The block tests that verify a scene's images: a pyramid of block means, from tiles of 8×8
// pixels up to the whole image, each tested on the replicates (Welch between two runs, or the
// paired t where they share random streams; Student's one-sample t against an exact image).
//
// Why blocks, and why every scale: one test per pixel would need R large enough for every
// pixel's mean to be normal and a correction over millions of tests, which leaves no power. The
// mean of a tile of 8×8 pixels averages 64 pixels per replicate, so its R replicate values are
// close to normal, and a bias confined to a small region moves its tile's mean. A bias that spans
// a region moves the mean of every block that holds it, and the mean of a block of n tiles has
// about 1/√n the standard error of one tile: a 3% darkening of the whole image that no 8×8 tile
// can see is plain in the whole image's mean. So the scales are tile·2^k for k = 0, 1, ... until
// one block covers the image (edge blocks are cut by the border).
//
// The false-alarm budget is split equally between the L scales, and within a scale equally
// between its tests: a weighted Holm procedure over all the pyramid's tests with weight
// 1 / (L · n_s) for a test of scale s (n_s tests there). The few coarse tests are then held to
// alpha / (L · n_s), not diluted by the many fine ones (a flat Holm over the ~4T/3 tests would
// hold the whole image to 3 alpha / 4T and gain almost nothing), and the family-wise error over
// the whole pyramid stays at most alpha. As for runs (statistics.h), every standard error is the
// spread across replicates.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "results/image.h"

namespace pcbench {

struct PyramidOptions {
  std::uint32_t tile = 8;  // the finest block's edge in pixels
  double bright_fraction = 0.1;
  double power = 0.8;  // of the minimum detectable bias
  // How many tested verdicts the comparison is decided with, itself included: a session adjusts
  // the comparison's p-value again with Holm over its whole family (statistics.h,
  // decide_family). The detectable bias is computed at the threshold that then decides, the
  // share alpha / (family_size × L × n_s) of a test at scale s: the first step of both Holm
  // procedures (their later steps are less strict, so the figure is conservative, never
  // optimistic). 1 for a comparison decided alone.
  std::uint32_t family_size = 1;
  // How many scales to test, finest first; 0: every scale up to the whole image. 1 tests the
  // tiles alone.
  std::uint32_t max_scales = 0;
  // compare_blocks only: replicate r of a and of b come from the same random streams (runs with
  // paired streams, share_streams in harness/plan/plan.h), so the two sides are correlated and
  // Welch's test, which needs them independent, does not apply. Each block is then tested on
  // the R replicate differences of its means (paired t, dof R - 1); the pairs are independent of
  // each other. Where the runs correlate positively the differences vary less than the sides
  // do, and the detectable bias shrinks with them. Needs as many replicates on both sides.
  bool paired = false;
};

struct BlockTest {
  std::uint32_t x = 0, y = 0, channel = 0;  // the block's column and row at its scale
  double mean_a = 0, mean_b = 0;  // block means (b: the other run, the exact or reference mean)
  double statistic = 0, dof = 0, p_value = 1;
  double p_adjusted = 1;  // weighted Holm over the whole pyramid
  // Block mean (average of a and b) > 0 and >= bright_fraction × the image mean of the channel.
  bool bright = false;
  // Absolute, at `power`, for a two-sided test at the scale's detection_share, with the Student
  // quantiles of the block test's dof.
  double min_detectable_bias = 0;
};

struct ScaleTests {
  std::uint32_t block = 0;  // edge in pixels
  std::uint32_t columns = 0, rows = 0;
  std::vector<BlockTest> tests = {};  // blocks row by row, then channel within a block
  // The share of alpha each test's raw p-value is held to for the power statement:
  // alpha / (family_size × scales × tests.size()).
  double detection_share = 0;
  double min_p_adjusted = 1;
  // Max over bright tests of min_detectable_bias / block mean: the largest bias relative to the
  // block's mean that this scale may have missed. NaN if some bright test's is NaN, 0 without
  // bright tests.
  double worst_bright_relative_mdb = 0;
  // The median of the same ratios over the bright tests: what a typical bright block may hide
  // (the worst is often one dim edge block, and reads as typical when stated alone). NaN as the
  // worst, 0 without bright tests.
  double median_bright_relative_mdb = 0;
  std::uint32_t bright_tests = 0;
};

struct PyramidResult {
  std::vector<ScaleTests> scales = {};  // the tiles first, the whole image last
  std::uint32_t tests = 0;              // over every scale
  double min_p_adjusted = 1;            // the comparison's p-value
  bool rejected = false;                // min_p_adjusted <= alpha (the comparison decided alone)
  bool paired = false;                  // tested on replicate differences (PyramidOptions)
};

// Per block and channel, each replicate's block mean is one observation; the R_a observations of
// a against the R_b of b give Welch's two-sample test (the paired test with options.paired). A
// block with zero variance on both sides is tested exactly (p = 1 for equal means, 0 otherwise). A
// block holding a non-finite value gets p = 0: a NaN or inf pixel is a defect that must not pass.
// Throws std::invalid_argument for fewer than 2 replicates on a side, images of different sizes, an
// empty image, alpha outside (0, 1), tile 0, power outside (0, 1), family_size 0, or paired sides
// of different replicate counts.
PyramidResult compare_blocks(std::span<const Image> a, std::span<const Image> b, double alpha,
                             const PyramidOptions& options = {});

// The same against an exact image: a one-sample t test (dof R - 1) of the replicate block means
// against the exact block mean.
PyramidResult test_blocks_against_exact(std::span<const Image> a, const Image& exact, double alpha,
                                        const PyramidOptions& options = {});

// The same against a converged reference image with its own per-pixel standard error (another
// renderer's reference): Welch's test of the replicate block means against the reference block
// mean, whose variance is the sum of its pixels' se² over the block's pixel count squared
// (pixels taken as independent) with infinite dof. Where every se is 0 this is
// test_blocks_against_exact. Throws as test_blocks_against_exact, and for a stderr image of
// another size.
PyramidResult test_blocks_against_reference(std::span<const Image> a, const Image& reference,
                                            const Image& reference_stderr, double alpha,
                                            const PyramidOptions& options = {});

// The edges of the pyramid's blocks for a width × height image: tile, 2 tile, 4 tile, ... up to
// the first that covers the image (at most max_scales of them; 0: all).
std::vector<std::uint32_t> pyramid_block_sizes(std::uint32_t width, std::uint32_t height,
                                               std::uint32_t tile, std::uint32_t max_scales = 0);

// How many times both runs' samples per pixel would bring a relative detectable bias down to
// `required` at the same replicate count: (mdb / required)², as the detectable bias goes with
// the standard errors, hence with 1/sqrt(samples per pixel) (the t quantiles depend on the
// replicate count only). Below 1: the requirement is met already.
inline double samples_factor(double relative_mdb, double required) {
  const double r = relative_mdb / required;
  return r * r;
}

}  // namespace pcbench
