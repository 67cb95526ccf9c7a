// The block pyramid (harness/verify/block_pyramid.h): the tiles' tests decided alone (the finest
// scale, as every comparison tested them before the pyramid), then the pyramid's scales, its
// weighted Holm budget and what a coarse scale finds that the tiles cannot.
#include "harness/verify/block_pyramid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "base/errors.h"
#include "harness/plan/scale_requirements.h"
#include "harness/run/diagnostics.h"
#include "harness/verify/block_checks.h"
#include "harness/verify/statistics.h"
#include "tests/synthetic_images.h"

namespace pcbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kAlpha = 0.01;
constexpr double kRequired = 0.05;

// The tiles alone: the pyramid cut to its finest scale, decided as a family of its own.
ScaleTests compare_tiles(std::span<const Image> a, std::span<const Image> b, double alpha,
                         PyramidOptions options = {}) {
  options.max_scales = 1;
  return compare_blocks(a, b, alpha, options).scales.at(0);
}
ScaleTests test_tiles_against_exact(std::span<const Image> a, const Image& exact, double alpha,
                                    PyramidOptions options = {}) {
  options.max_scales = 1;
  return test_blocks_against_exact(a, exact, alpha, options).scales.at(0);
}

// Adds `bias` to one channel of one tile (tile x tile pixels) of every image.
void add_to_tile(std::vector<Image>& images, std::uint32_t tx, std::uint32_t ty,
                 std::uint32_t channel, double bias, std::uint32_t tile = 8) {
  for (Image& image : images) {
    for (std::uint32_t y = ty * tile; y < std::min(image.height, (ty + 1) * tile); ++y) {
      for (std::uint32_t x = tx * tile; x < std::min(image.width, (tx + 1) * tile); ++x) {
        image.at(x, y, channel) += bias;
      }
    }
  }
}

const BlockTest& find_tile(const ScaleTests& result, std::uint32_t tx, std::uint32_t ty,
                           std::uint32_t channel) {
  for (const BlockTest& t : result.tests) {
    if (t.x == tx && t.y == ty && t.channel == channel) return t;
  }
  throw std::logic_error("no such tile");
}

const BlockTest& smallest_p_adjusted(const ScaleTests& result) {
  return *std::min_element(
      result.tests.begin(), result.tests.end(),
      [](const BlockTest& a, const BlockTest& b) { return a.p_adjusted < b.p_adjusted; });
}

// ---------------------------------------------------------------------------------------------
// Tile tests

constexpr std::uint32_t kWidth = 64, kHeight = 48, kReplicates = 8;
constexpr double kSd = 0.5;

TEST(BlockPyramidTiles, SameDistributionIsNotRejected) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 11, kSd);
  const std::vector<Image> b = normal_replicates(kWidth, kHeight, kReplicates, 12, kSd);
  const ScaleTests result = compare_tiles(a, b, kAlpha);
  EXPECT_EQ(result.tests.size(), 8u * 6u * 3u);
  EXPECT_FALSE((result.min_p_adjusted <= kAlpha));
  EXPECT_GT(result.min_p_adjusted, 0.2);
  // Every tile is within 10x of the image mean, so all are bright.
  EXPECT_EQ(result.bright_tests, result.tests.size());

  // The raw p-values of independent tiles are uniform when the means agree.
  std::vector<double> p;
  for (const BlockTest& t : result.tests) p.push_back(t.p_value);
  EXPECT_GT(ks_uniform(p).p_value, 0.01);

  // The detectable bias scales the standard error of the difference of two tile means, each the
  // mean of R tile averages of 64 pixels: sqrt(2 sd² / 64 / R); Welch's dof is at most 14.
  const double stderr_of_difference = std::sqrt(2.0 * kSd * kSd / 64.0 / kReplicates);
  const double expected = detectable_multiplier(kAlpha / static_cast<double>(result.tests.size()),
                                                2.0 * (kReplicates - 1)) *
                          stderr_of_difference;
  double sum = 0.0, worst = 0.0;
  for (const BlockTest& t : result.tests) {
    EXPECT_LE(t.dof, 2.0 * (kReplicates - 1) + 1e-9);
    EXPECT_GE(t.dof, kReplicates - 1 - 1e-9);
    sum += t.min_detectable_bias;
    worst = std::max(worst, t.min_detectable_bias / (0.5 * (t.mean_a + t.mean_b)));
  }
  const double ratio = sum / static_cast<double>(result.tests.size()) / expected;
  EXPECT_GT(ratio, 0.9) << expected;
  EXPECT_LT(ratio, 1.3) << expected;
  EXPECT_DOUBLE_EQ(result.worst_bright_relative_mdb, worst);

  // Holm's adjusted p-values are at least the raw ones.
  for (const BlockTest& t : result.tests) EXPECT_GE(t.p_adjusted, t.p_value);
}

TEST(BlockPyramidTiles, BiasOfTwiceTheDetectableIsFoundOnItsTile) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 21, kSd);
  std::vector<Image> b = normal_replicates(kWidth, kHeight, kReplicates, 22, kSd);
  const ScaleTests before = compare_tiles(a, b, kAlpha);
  ASSERT_FALSE((before.min_p_adjusted <= kAlpha));
  constexpr std::uint32_t kTx = 5, kTy = 2;
  for (std::uint32_t c = 0; c < kImageChannels; ++c) {
    const BlockTest& t = find_tile(before, kTx, kTy, c);
    ASSERT_GT(t.min_detectable_bias, 0.0);
    add_to_tile(b, kTx, kTy, c, 2.0 * t.min_detectable_bias);
  }
  const ScaleTests after = compare_tiles(a, b, kAlpha);
  EXPECT_TRUE((after.min_p_adjusted <= kAlpha));
  const BlockTest& smallest = smallest_p_adjusted(after);
  EXPECT_EQ(smallest.x, kTx);
  EXPECT_EQ(smallest.y, kTy);
  EXPECT_LE(smallest.p_adjusted, kAlpha);
  EXPECT_EQ(after.min_p_adjusted, smallest.p_adjusted);
  for (std::uint32_t c = 0; c < kImageChannels; ++c) {
    EXPECT_LE(find_tile(after, kTx, kTy, c).p_adjusted, kAlpha) << "channel " << c;
  }
}

// The samples factor: images whose noise is halved around the same means (what 4× the samples
// per pixel does to a standard error) halve the detectable bias, so the factor falls 4×, and
// the factor the noisier pair reports brings it to the requirement.
TEST(BlockPyramidTiles, SamplesFactorPredictsTheRequiredPower) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 31, kSd);
  const std::vector<Image> b = normal_replicates(kWidth, kHeight, kReplicates, 32, kSd);
  const Image mean = truth(kWidth, kHeight);
  const auto shrunk = [&](std::vector<Image> images, double by) {
    for (Image& image : images) {
      for (std::size_t i = 0; i < image.values.size(); ++i) {
        image.values[i] = mean.values[i] + (image.values[i] - mean.values[i]) / by;
      }
    }
    return images;
  };
  const double mdb = compare_tiles(a, b, kAlpha).worst_bright_relative_mdb;
  const double half =
      compare_tiles(shrunk(a, 2.0), shrunk(b, 2.0), kAlpha).worst_bright_relative_mdb;
  ASSERT_GT(samples_factor(mdb, kRequired), 1.0);
  EXPECT_NEAR(samples_factor(half, kRequired), samples_factor(mdb, kRequired) / 4.0,
              1e-2 * samples_factor(mdb, kRequired));
  const double by = std::sqrt(samples_factor(mdb, kRequired));
  EXPECT_NEAR(compare_tiles(shrunk(a, by), shrunk(b, by), kAlpha).worst_bright_relative_mdb,
              kRequired, 1e-2 * kRequired);
}

TEST(BlockPyramidTiles, AgainstExactImage) {
  const Image exact = truth(kWidth, kHeight);
  std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 31, kSd);
  const ScaleTests before = test_tiles_against_exact(a, exact, kAlpha);
  EXPECT_EQ(before.tests.size(), 8u * 6u * 3u);
  EXPECT_FALSE((before.min_p_adjusted <= kAlpha));
  EXPECT_GT(before.min_p_adjusted, 0.2);
  std::vector<double> p;
  for (const BlockTest& t : before.tests) {
    p.push_back(t.p_value);
    EXPECT_EQ(t.dof, kReplicates - 1.0);  // one-sample Student's t
  }
  EXPECT_GT(ks_uniform(p).p_value, 0.01);
  // The exact tile mean is the average of the exact pixels.
  double sum = 0.0;
  for (std::uint32_t y = 8; y < 16; ++y) {
    for (std::uint32_t x = 16; x < 24; ++x) sum += exact.at(x, y, 1);
  }
  EXPECT_NEAR(find_tile(before, 2, 1, 1).mean_b, sum / 64.0, 1e-14);

  constexpr std::uint32_t kTx = 1, kTy = 4;
  for (std::uint32_t c = 0; c < kImageChannels; ++c) {
    add_to_tile(a, kTx, kTy, c, -2.0 * find_tile(before, kTx, kTy, c).min_detectable_bias);
  }
  const ScaleTests after = test_tiles_against_exact(a, exact, kAlpha);
  EXPECT_TRUE((after.min_p_adjusted <= kAlpha));
  const BlockTest& smallest = smallest_p_adjusted(after);
  EXPECT_EQ(smallest.x, kTx);
  EXPECT_EQ(smallest.y, kTy);
  EXPECT_LT(smallest.statistic, 0.0);
}

// 20x12 in tiles of 8: 3x2 tiles, the right column 4 wide and the bottom row 4 high.
TEST(BlockPyramidTiles, PartialEdgeTiles) {
  std::vector<Image> a(3, Image(20, 12));
  for (std::uint32_t r = 0; r < a.size(); ++r) {
    for (std::uint32_t y = 0; y < 12; ++y) {
      for (std::uint32_t x = 0; x < 20; ++x) {
        for (std::uint32_t c = 0; c < kImageChannels; ++c) {
          a[r].at(x, y, c) = x + 100.0 * y + r + 1000.0 * c;
        }
      }
    }
  }
  const ScaleTests same = compare_tiles(a, a, kAlpha);
  EXPECT_EQ(same.tests.size(), 18u);
  ASSERT_EQ(same.tests.size(), 18u);
  // Tiles in rows of tiles, channels within a tile.
  EXPECT_EQ(same.tests[3].x, 1u);
  EXPECT_EQ(same.tests[3].channel, 0u);
  EXPECT_EQ(same.tests[17].x, 2u);
  EXPECT_EQ(same.tests[17].y, 1u);
  EXPECT_EQ(same.tests[17].channel, 2u);
  // Corner tile: x 16..19, y 8..11; replicates 0, 1, 2 average to 1.
  const BlockTest& corner = find_tile(same, 2, 1, 2);
  EXPECT_DOUBLE_EQ(corner.mean_a, 17.5 + 950.0 + 1.0 + 2000.0);
  EXPECT_DOUBLE_EQ(corner.mean_b, corner.mean_a);
  EXPECT_DOUBLE_EQ(find_tile(same, 2, 0, 0).mean_a, 17.5 + 350.0 + 1.0);  // y 0..7
  EXPECT_DOUBLE_EQ(find_tile(same, 0, 1, 0).mean_a, 3.5 + 950.0 + 1.0);   // x 0..7
  for (const BlockTest& t : same.tests) EXPECT_EQ(t.p_value, 1.0);
  EXPECT_FALSE((same.min_p_adjusted <= kAlpha));

  // Against the exact mean image (each pixel's average over the replicates): the tile means of
  // the replicates spread by 1 around it.
  Image exact = a[1];
  const ScaleTests against = test_tiles_against_exact(a, exact, kAlpha);
  EXPECT_EQ(against.tests.size(), 18u);
  EXPECT_DOUBLE_EQ(find_tile(against, 2, 1, 0).mean_b, 17.5 + 950.0 + 1.0);
  EXPECT_NEAR(find_tile(against, 2, 1, 0).p_value, 1.0, 1e-12);

  // A 4-pixel tile size on the same image: 5x3 tiles, none partial.
  EXPECT_EQ(compare_tiles(a, a, kAlpha, {.tile = 4}).tests.size(), 45u);
  // A tile larger than the image: one tile per channel.
  EXPECT_EQ(compare_tiles(a, a, kAlpha, {.tile = 64}).tests.size(), 3u);
  // The two sides may have different replicate counts.
  EXPECT_GT(compare_tiles(a, std::span(a).first(2), kAlpha).min_p_adjusted, kAlpha);
}

TEST(BlockPyramidTiles, ConstantReplicatesAreTestedExactly) {
  const std::vector<Image> a(2, truth(10, 10));
  std::vector<Image> b = a;
  const ScaleTests same = compare_tiles(a, b, kAlpha);
  EXPECT_EQ(same.tests.size(), 12u);
  EXPECT_FALSE((same.min_p_adjusted <= kAlpha));
  EXPECT_EQ(same.min_p_adjusted, 1.0);
  for (const BlockTest& t : same.tests) {
    EXPECT_EQ(t.p_value, 1.0);
    EXPECT_EQ(t.min_detectable_bias, 0.0);
  }
  EXPECT_EQ(same.worst_bright_relative_mdb, 0.0);
  add_to_tile(b, 1, 0, 2, 1e-9);
  const ScaleTests differ = compare_tiles(a, b, kAlpha);
  EXPECT_TRUE((differ.min_p_adjusted <= kAlpha));
  EXPECT_EQ(find_tile(differ, 1, 0, 2).p_value, 0.0);
  EXPECT_EQ(find_tile(differ, 1, 0, 2).statistic, -kInf);
  EXPECT_EQ(find_tile(differ, 1, 0, 1).p_value, 1.0);
}

TEST(BlockPyramidTiles, NonFiniteValueIsRejected) {
  const std::vector<Image> a = normal_replicates(16, 16, 4, 41, kSd);
  std::vector<Image> b = normal_replicates(16, 16, 4, 42, kSd);
  b[2].at(9, 3, 1) = std::nan("");
  const ScaleTests result = compare_tiles(a, b, kAlpha);
  EXPECT_TRUE((result.min_p_adjusted <= kAlpha));
  EXPECT_EQ(result.min_p_adjusted, 0.0);
  const BlockTest& bad = find_tile(result, 1, 0, 1);
  EXPECT_EQ(bad.p_value, 0.0);
  EXPECT_TRUE(std::isnan(bad.min_detectable_bias));
  EXPECT_GT(find_tile(result, 0, 0, 1).p_value, 0.0);
}

TEST(BlockPyramidTiles, BrightTilesAndTheirPower) {
  // Black except one bright tile: only that one is bright (0 is never bright), and its relative
  // detectable bias is its detectable bias over its mean.
  std::vector<Image> a(4, Image(16, 8)), b(4, Image(16, 8));
  for (std::uint32_t r = 0; r < 4; ++r) {
    a[r].at(9, 2, 0) = 10.0 + r;
    b[r].at(9, 2, 0) = 10.0 + 2.0 * r;
  }
  const ScaleTests result = compare_tiles(a, b, kAlpha);
  EXPECT_EQ(result.bright_tests, 1u);
  const BlockTest& bright = find_tile(result, 1, 0, 0);
  EXPECT_TRUE(bright.bright);
  EXPECT_GT(bright.min_detectable_bias, 0.0);
  EXPECT_DOUBLE_EQ(result.worst_bright_relative_mdb,
                   bright.min_detectable_bias / (0.5 * (bright.mean_a + bright.mean_b)));
  // Its detectable bias is detectable_multiplier at the Bonferroni share times the test's se.
  std::vector<double> ta, tb;
  for (std::uint32_t r = 0; r < 4; ++r) {
    ta.push_back(a[r].at(9, 2, 0) / 64.0);
    tb.push_back(b[r].at(9, 2, 0) / 64.0);
  }
  const TwoSampleTest welch = welch_two_sample(ta, tb);
  EXPECT_DOUBLE_EQ(bright.p_value, welch.p_value);
  EXPECT_DOUBLE_EQ(bright.min_detectable_bias,
                   detectable_multiplier(kAlpha / 6.0, welch.dof) * welch.stderr_of_difference);
  // A lower power asks for a smaller detectable bias.
  const ScaleTests lower = compare_tiles(a, b, kAlpha, {.power = 0.5});
  EXPECT_LT(find_tile(lower, 1, 0, 0).min_detectable_bias, bright.min_detectable_bias);
  // Decided in a family of 40 verdicts, the tile is held to alpha / (40 × 6): the detectable bias
  // is computed at that share, and the reported share says so.
  const ScaleTests in_family = compare_tiles(a, b, kAlpha, {.family_size = 40});
  EXPECT_DOUBLE_EQ(in_family.detection_share, kAlpha / 240.0);
  EXPECT_DOUBLE_EQ(result.detection_share, kAlpha / 6.0);
  EXPECT_DOUBLE_EQ(find_tile(in_family, 1, 0, 0).min_detectable_bias,
                   detectable_multiplier(kAlpha / 240.0, welch.dof) * welch.stderr_of_difference);
  EXPECT_GT(in_family.worst_bright_relative_mdb, result.worst_bright_relative_mdb);
  // The decision of the comparison alone is unchanged; only the power statement moves.
  EXPECT_EQ(in_family.min_p_adjusted, result.min_p_adjusted);
}

// The self-check's target: the tile and channel with the largest mean of a.
TEST(BlockPyramidTiles, BrightestTile) {
  std::vector<Image> a(2, Image(16, 8)), b(2, Image(16, 8));
  a[0].at(3, 5, 2) = 7.0;
  a[1].at(3, 5, 2) = 9.0;
  const ScaleTests result = compare_tiles(a, b, kAlpha);
  const BlockTest& brightest = brightest_block(result);
  EXPECT_EQ(brightest.x, 0u);
  EXPECT_EQ(brightest.y, 0u);
  EXPECT_EQ(brightest.channel, 2u);
  EXPECT_THROW(brightest_block(ScaleTests{}), std::invalid_argument);
}

TEST(BlockPyramidTiles, RejectsBadArguments) {
  const std::vector<Image> a(2, Image(4, 4));
  EXPECT_THROW(compare_tiles(std::span(a).first(1), a, kAlpha), std::invalid_argument);
  EXPECT_THROW(compare_tiles(a, std::span(a).first(1), kAlpha), std::invalid_argument);
  EXPECT_THROW(compare_tiles(a, std::vector<Image>(2, Image(4, 5)), kAlpha), std::invalid_argument);
  EXPECT_THROW(compare_tiles(std::vector<Image>(2), std::vector<Image>(2), kAlpha),
               std::invalid_argument);
  EXPECT_THROW(compare_tiles(a, a, 0.0), std::invalid_argument);
  EXPECT_THROW(compare_tiles(a, a, kAlpha, {.tile = 0}), std::invalid_argument);
  EXPECT_THROW(compare_tiles(a, a, kAlpha, {.power = 1.0}), std::invalid_argument);
  EXPECT_THROW(compare_tiles(a, a, kAlpha, {.family_size = 0}), std::invalid_argument);
  EXPECT_THROW(test_tiles_against_exact(std::span(a).first(1), a[0], kAlpha),
               std::invalid_argument);
  EXPECT_THROW(test_tiles_against_exact(a, Image(5, 4), kAlpha), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// The pyramid

TEST(BlockPyramidScales, TileTimesPowersOfTwoUntilOneBlockCoversTheImage) {
  EXPECT_EQ(pyramid_block_sizes(64, 48, 8), (std::vector<std::uint32_t>{8, 16, 32, 64}));
  EXPECT_EQ(pyramid_block_sizes(128, 128, 8), (std::vector<std::uint32_t>{8, 16, 32, 64, 128}));
  EXPECT_EQ(pyramid_block_sizes(20, 12, 8), (std::vector<std::uint32_t>{8, 16, 32}));
  EXPECT_EQ(pyramid_block_sizes(100, 8, 8), (std::vector<std::uint32_t>{8, 16, 32, 64, 128}));
  EXPECT_EQ(pyramid_block_sizes(4, 4, 8), (std::vector<std::uint32_t>{8}));
  EXPECT_EQ(pyramid_block_sizes(64, 48, 8, 2), (std::vector<std::uint32_t>{8, 16}));
  EXPECT_TRUE(pyramid_block_sizes(64, 48, 0).empty());
}

// Every coarse block's mean is its pixels' mean (edge blocks cut by the border), whatever the
// scale; the last scale is one block, the image mean.
TEST(BlockPyramidScales, CoarseBlockMeansAreTheirPixelsMeans) {
  std::vector<Image> a = normal_replicates(20, 12, 3, 5, kSd);
  const PyramidResult p = compare_blocks(a, a, kAlpha);
  ASSERT_EQ(p.scales.size(), 3u);
  EXPECT_EQ(p.tests, 3u * (6 + 2 + 1));
  const auto direct = [&](std::uint32_t block, std::uint32_t bx, std::uint32_t by,
                          std::uint32_t c) {
    double sum = 0.0, count = 0.0;
    for (const Image& image : a) {
      for (std::uint32_t y = by * block; y < std::min(12u, (by + 1) * block); ++y) {
        for (std::uint32_t x = bx * block; x < std::min(20u, (bx + 1) * block); ++x) {
          sum += image.at(x, y, c);
          count += 1.0;
        }
      }
    }
    return sum / count;
  };
  for (const ScaleTests& scale : p.scales) {
    EXPECT_EQ(scale.tests.size(), std::size_t{scale.columns} * scale.rows * 3);
    for (const BlockTest& t : scale.tests) {
      EXPECT_NEAR(t.mean_a, direct(scale.block, t.x, t.y, t.channel), 1e-12)
          << scale.block << " " << t.x << "," << t.y;
      EXPECT_EQ(t.p_value, 1.0);  // a against itself
    }
  }
  EXPECT_EQ(p.scales[1].columns, 2u);
  EXPECT_EQ(p.scales[1].rows, 1u);
  EXPECT_EQ(p.scales[2].columns, 1u);
}

// The budget: alpha split equally between the scales, then between a scale's tests; the
// detectable bias of a scale is computed at that share (times the family's size).
TEST(BlockPyramidBudget, EachScaleGetsItsShareOfAlpha) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 61, kSd);
  const std::vector<Image> b = normal_replicates(kWidth, kHeight, kReplicates, 62, kSd);
  const PyramidResult p = compare_blocks(a, b, kAlpha, {.family_size = 5});
  ASSERT_EQ(p.scales.size(), 4u);  // 8, 16, 32, 64 over 64x48
  std::size_t tests = 0;
  for (const ScaleTests& scale : p.scales) {
    EXPECT_DOUBLE_EQ(scale.detection_share,
                     kAlpha / (5.0 * 4.0 * static_cast<double>(scale.tests.size())));
    for (const BlockTest& t : scale.tests) {
      EXPECT_DOUBLE_EQ(t.min_detectable_bias, detectable_multiplier(scale.detection_share, t.dof) *
                                                  std::fabs(t.mean_a - t.mean_b) /
                                                  std::fabs(t.statistic))
          << scale.block;
      // The weighted Holm's first step: a test of weight 1 / (L n_s) is adjusted to at least
      // L n_s times its p.
      EXPECT_GE(
          t.p_adjusted,
          std::min(1.0, 4.0 * static_cast<double>(scale.tests.size()) * t.p_value) * (1 - 1e-12));
    }
    tests += scale.tests.size();
  }
  EXPECT_EQ(p.tests, tests);
  EXPECT_GT(p.min_p_adjusted, kAlpha);
  // The whole image's mean averages all 3072 pixels: its detectable bias is far below a tile's.
  EXPECT_LT(p.scales.back().worst_bright_relative_mdb,
            0.25 * p.scales.front().worst_bright_relative_mdb);
}

// What the pyramid is for: a bias over the whole image, below what any one tile can see, is
// found at the image scale; the tiles alone miss it. Its reason is the coarse scales' power.
TEST(BlockPyramidBudget, GlobalBiasBelowTheTilesIsFoundAtTheImageScale) {
  // 128x96: 192 tiles, so that the image's mean has about 1/14 of a tile mean's standard error.
  constexpr std::uint32_t kW = 128, kH = 96;
  const std::vector<Image> a = normal_replicates(kW, kH, kReplicates, 71, kSd);
  std::vector<Image> b = normal_replicates(kW, kH, kReplicates, 72, kSd);
  const PyramidResult before = compare_blocks(a, b, kAlpha);
  ASSERT_GT(before.min_p_adjusted, kAlpha);
  const double image_mdb = before.scales.back().tests[1].min_detectable_bias;
  const double tile_mdb = before.scales.front().tests[1].min_detectable_bias;
  ASSERT_LT(2.0 * image_mdb, 0.2 * tile_mdb);
  for (Image& image : b) {
    for (std::uint32_t y = 0; y < kH; ++y) {
      for (std::uint32_t x = 0; x < kW; ++x) image.at(x, y, 1) += 2.0 * image_mdb;
    }
  }
  const PyramidResult after = compare_blocks(a, b, kAlpha);
  EXPECT_LE(after.min_p_adjusted, kAlpha);
  EXPECT_LE(after.scales.back().min_p_adjusted, kAlpha);
  EXPECT_EQ(after.min_p_adjusted, after.scales.back().min_p_adjusted);
  EXPECT_GT(compare_tiles(a, b, kAlpha).min_p_adjusted, kAlpha);
}

// Against a reference with its own standard error, a block's reference variance is the sum of
// its pixels' se² over the pixel count squared, at every scale.
TEST(BlockPyramidBudget, ReferenceVarianceAddsUpOverABlock) {
  const std::vector<Image> a = normal_replicates(16, 16, 4, 81, kSd);
  const Image reference = truth(16, 16);
  Image stderr_image(16, 16);
  for (double& v : stderr_image.values) v = 0.2;
  const PyramidResult exact = test_blocks_against_exact(a, reference, kAlpha);
  const PyramidResult with_se = test_blocks_against_reference(a, reference, stderr_image, kAlpha);
  ASSERT_EQ(with_se.scales.size(), 2u);
  for (std::size_t s = 0; s < 2; ++s) {
    const double pixels = std::pow(with_se.scales[s].block, 2);
    for (std::size_t k = 0; k < with_se.scales[s].tests.size(); ++k) {
      const BlockTest& e = exact.scales[s].tests[k];
      const BlockTest& r = with_se.scales[s].tests[k];
      const double se_a = (e.mean_a - e.mean_b) / e.statistic;
      const double se = (r.mean_a - r.mean_b) / r.statistic;
      EXPECT_NEAR(se * se, se_a * se_a + 0.04 / pixels, 1e-12);
    }
  }
}

// A same-distribution pair's pyramid keeps its false alarms below alpha (over many seeds, with
// the tests' correlation across scales): 200 pairs at alpha 0.1, at most 20 + a binomial
// margin expected; a flat, uncorrected test over the ~4T/3 tests would alarm almost always.
TEST(BlockPyramidBudget, FalseAlarmsStayBelowAlpha) {
  constexpr double kLooseAlpha = 0.1;
  int alarms = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const std::vector<Image> a = normal_replicates(32, 32, 4, 1000 + 2 * seed, kSd);
    const std::vector<Image> b = normal_replicates(32, 32, 4, 1001 + 2 * seed, kSd);
    alarms += compare_blocks(a, b, kLooseAlpha).min_p_adjusted <= kLooseAlpha;
  }
  // P(Binomial(200, 0.1) >= 32) < 0.005: the test's own error budget.
  EXPECT_LT(alarms, 32);
}

// A run on the same streams as `base`: each replicate is base's plus independent noise of `sd`
// per pixel (what the estimators do differently) and `bias` in every pixel of channel 1.
std::vector<Image> paired_with(const std::vector<Image>& base, std::uint64_t seed, double sd,
                               double bias = 0.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sd);
  std::vector<Image> images = base;
  for (Image& image : images) {
    for (std::uint32_t y = 0; y < image.height; ++y) {
      for (std::uint32_t x = 0; x < image.width; ++x) {
        for (std::uint32_t c = 0; c < kImageChannels; ++c) {
          image.at(x, y, c) += normal(rng) + (c == 1 ? bias : 0.0);
        }
      }
    }
  }
  return images;
}

// The paired design: where two runs share most of their noise, the differences of their
// replicates vary far less than either run, and a bias that Welch's test cannot see is found.
TEST(BlockPyramidPaired, SharedNoiseCancelsInTheDifferences) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 91, kSd);
  const std::vector<Image> b = paired_with(a, 92, 0.1 * kSd, 0.01);
  const PyramidResult welch = compare_blocks(a, b, kAlpha);
  const PyramidResult paired = compare_blocks(a, b, kAlpha, {.paired = true});
  EXPECT_FALSE(welch.paired);
  EXPECT_TRUE(paired.paired);
  EXPECT_GT(welch.min_p_adjusted, kAlpha);
  EXPECT_LE(paired.min_p_adjusted, kAlpha);
  for (std::size_t s = 0; s < paired.scales.size(); ++s) {
    // sd(a - b) = 0.1 sd against Welch's sqrt(2) sd: the detectable bias shrinks with it (less
    // than 14x: the paired test has R - 1 dof, Welch's about 2R - 2).
    EXPECT_LT(paired.scales[s].worst_bright_relative_mdb,
              0.2 * welch.scales[s].worst_bright_relative_mdb);
    for (const BlockTest& t : paired.scales[s].tests) EXPECT_EQ(t.dof, kReplicates - 1.0);
  }
  // The same images as one side: every difference is 0, so every test is exact and passes.
  const PyramidResult same = compare_blocks(a, a, kAlpha, {.paired = true});
  EXPECT_EQ(same.min_p_adjusted, 1.0);
  // Pairs need as many replicates on both sides.
  EXPECT_THROW(compare_blocks(a, std::span(b).first(kReplicates - 1), kAlpha, {.paired = true}),
               std::invalid_argument);
}

// The paired pyramid's false alarms on same-distribution pairs that share their noise stay
// below alpha, as Welch's do on independent pairs (FalseAlarmsStayBelowAlpha).
TEST(BlockPyramidPaired, FalseAlarmsStayBelowAlpha) {
  constexpr double kLooseAlpha = 0.1;
  int alarms = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const std::vector<Image> a = normal_replicates(32, 32, 4, 3000 + 2 * seed, kSd);
    const std::vector<Image> b = paired_with(a, 3001 + 2 * seed, 0.3 * kSd);
    alarms += compare_blocks(a, b, kLooseAlpha, {.paired = true}).min_p_adjusted <= kLooseAlpha;
  }
  // P(Binomial(200, 0.1) >= 32) < 0.005: the test's own error budget.
  EXPECT_LT(alarms, 32);
}

TEST(BlockPyramidBudget, WeightedHolm) {
  const std::vector<double> p = {0.01, 0.04, 0.03, 0.5};
  const std::vector<double> equal(4, 0.25);
  EXPECT_EQ(weighted_holm_adjusted(p, equal), holm_adjusted(p));
  // Weights 0.5, 0.25, 0.125, 0.125: ordered by p/w: 0.02 (i0), 0.16 (i1), 0.24 (i2), 4 (i3).
  const std::vector<double> w = {0.5, 0.25, 0.125, 0.125};
  const std::vector<double> adjusted = weighted_holm_adjusted(p, w);
  EXPECT_DOUBLE_EQ(adjusted[0], 0.02);
  EXPECT_DOUBLE_EQ(adjusted[1], 0.16 * 0.5);
  EXPECT_DOUBLE_EQ(adjusted[2], 0.16 * 0.5);  // 0.24 × 0.25 = 0.06, raised to the step before
  EXPECT_DOUBLE_EQ(adjusted[3], 4.0 * 0.125);
  // Step-down monotone: a later step never adjusts below an earlier one.
  EXPECT_DOUBLE_EQ(
      weighted_holm_adjusted(std::vector<double>{0.1, 0.1}, std::vector<double>{0.9, 0.1})[1],
      0.1 / 0.9);
  EXPECT_THROW(weighted_holm_adjusted(p, std::vector<double>{1.0}), std::invalid_argument);
  EXPECT_THROW(weighted_holm_adjusted(p, std::vector<double>{0.5, 0.5, 0.0, 0.0}),
               std::invalid_argument);
}

TEST(ScaleRequirements, DefaultsSettingAndTheScalesTheyName) {
  ScaleRequirements r;
  EXPECT_EQ(r.at(8, true, false), 0.05);
  EXPECT_EQ(r.at(128, false, true), 0.01);
  EXPECT_FALSE(r.at(32, false, false).has_value());
  // One block that is both the tiles and the image: the stricter.
  EXPECT_EQ(r.at(8, true, true), 0.01);
  r.set("32=0.05", "here");
  r.set("tile", 0.1, "here");
  EXPECT_EQ(r.at(32, false, false), 0.05);
  EXPECT_EQ(r.at(8, true, false), 0.1);
  EXPECT_NO_THROW(r.check_blocks(8, "here"));
  EXPECT_THROW(r.check_blocks(12, "here"), InputError);
  r.set("32=none", "here");
  EXPECT_FALSE(r.at(32, false, false).has_value());
  for (const char* bad : {"32", "image=0", "image=1", "tile=-0.1", "x=0.1", "0=0.1", "image=5%"}) {
    EXPECT_THROW(r.set(bad, "here"), InputError) << bad;
  }
  try {
    r.set("image=2", "suite.json: /require_mdb/image");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("suite.json: /require_mdb/image"), std::string::npos);
  }
}

}  // namespace
}  // namespace pcbench
