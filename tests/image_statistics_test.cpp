#include "harness/verify/image_statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/run/diagnostics.h"
#include "harness/verify/statistics.h"
#include "harness/verify/tile_checks.h"
#include "results/exr_file.h"
#include "test_support.h"

namespace pcbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kAlpha = 0.01;

// The true mean of a synthetic scene: smooth, positive, different per channel.
double true_mean(std::uint32_t x, std::uint32_t y, std::uint32_t c) {
  return 1.0 + 0.5 * std::sin(0.3 * x) * std::cos(0.2 * y) + 0.2 * c;
}

Image truth(std::uint32_t width, std::uint32_t height) {
  Image image(width, height);
  for (std::uint32_t y = 0; y < height; ++y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      for (std::uint32_t c = 0; c < kImageChannels; ++c) image.at(x, y, c) = true_mean(x, y, c);
    }
  }
  return image;
}

// R replicates of a sampler whose pixels are independent normals around true_mean.
std::vector<Image> normal_replicates(std::uint32_t width, std::uint32_t height, std::uint32_t count,
                                     std::uint64_t seed, double sd) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sd);
  std::vector<Image> images;
  for (std::uint32_t r = 0; r < count; ++r) {
    Image image = truth(width, height);
    for (double& v : image.values) v += normal(rng);
    images.push_back(std::move(image));
  }
  return images;
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

const TileTest& find_tile(const TileTestResult& result, std::uint32_t tx, std::uint32_t ty,
                          std::uint32_t channel) {
  for (const TileTest& t : result.tiles) {
    if (t.tile_x == tx && t.tile_y == ty && t.channel == channel) return t;
  }
  throw std::logic_error("no such tile");
}

const TileTest& smallest_p_adjusted(const TileTestResult& result) {
  return *std::min_element(
      result.tiles.begin(), result.tiles.end(),
      [](const TileTest& a, const TileTest& b) { return a.p_adjusted < b.p_adjusted; });
}

// ---------------------------------------------------------------------------------------------
// pixel_statistics and z_map

TEST(ImageStatisticsPixels, KnownNumbers) {
  std::vector<Image> images(3, Image(2, 1));
  for (std::uint32_t r = 0; r < 3; ++r) {
    images[r].at(0, 0, 0) = 1.0 + r;              // 1, 2, 3: mean 2, sd 1
    images[r].at(1, 0, 2) = 5.0;                  // constant: se 0
    images[r].at(1, 0, 1) = r == 0 ? -4.0 : 2.0;  // -4, 2, 2: mean 0, sd sqrt(12)
  }
  const PixelStatistics s = pixel_statistics(images);
  EXPECT_EQ(s.replicates, 3u);
  EXPECT_EQ(s.mean.width, 2u);
  EXPECT_EQ(s.mean.height, 1u);
  EXPECT_DOUBLE_EQ(s.mean.at(0, 0, 0), 2.0);
  EXPECT_DOUBLE_EQ(s.standard_error.at(0, 0, 0), 1.0 / std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(s.mean.at(1, 0, 2), 5.0);
  EXPECT_EQ(s.standard_error.at(1, 0, 2), 0.0);
  EXPECT_DOUBLE_EQ(s.mean.at(1, 0, 1), 0.0);
  EXPECT_DOUBLE_EQ(s.standard_error.at(1, 0, 1), 2.0);  // sqrt(12 / 3)
  EXPECT_EQ(s.mean.at(0, 0, 1), 0.0);
  EXPECT_EQ(s.standard_error.at(0, 0, 1), 0.0);
}

TEST(ImageStatisticsPixels, RejectsFewReplicatesAndMixedSizes) {
  EXPECT_THROW(pixel_statistics(std::vector<Image>{}), std::invalid_argument);
  EXPECT_THROW(pixel_statistics(std::vector<Image>{Image(2, 2)}), std::invalid_argument);
  EXPECT_THROW(pixel_statistics(std::vector<Image>{Image(2, 2), Image(2, 3)}),
               std::invalid_argument);
  Image broken(2, 2);
  broken.values.pop_back();
  EXPECT_THROW(pixel_statistics(std::vector<Image>{Image(2, 2), broken}), std::invalid_argument);
}

TEST(ImageStatisticsZMap, TwoSidesAndExact) {
  PixelStatistics a{Image(2, 1), Image(2, 1), 4}, b{Image(2, 1), Image(2, 1), 4};
  a.mean.at(0, 0, 0) = 3.0, a.standard_error.at(0, 0, 0) = 0.3;
  b.mean.at(0, 0, 0) = 2.0, b.standard_error.at(0, 0, 0) = 0.4;
  a.mean.at(0, 0, 1) = 1.0;  // both se 0, means differ: certain
  b.mean.at(0, 0, 2) = 1.0;
  a.mean.at(1, 0, 0) = 7.0, b.mean.at(1, 0, 0) = 7.0;  // both se 0, equal: 0, not NaN
  const Image z = z_map(a, b);
  EXPECT_DOUBLE_EQ(z.at(0, 0, 0), 2.0);  // 1 / sqrt(0.09 + 0.16)
  EXPECT_EQ(z.at(0, 0, 1), kInf);
  EXPECT_EQ(z.at(0, 0, 2), -kInf);
  EXPECT_EQ(z.at(1, 0, 0), 0.0);
  EXPECT_EQ(z.at(1, 0, 1), 0.0);

  Image exact(2, 1);
  exact.at(0, 0, 0) = 3.6;
  exact.at(1, 0, 0) = 7.0;
  const Image ze = z_map(a, exact);
  EXPECT_NEAR(ze.at(0, 0, 0), -2.0, 1e-12);  // (3 - 3.6) / 0.3
  EXPECT_EQ(ze.at(0, 0, 1), kInf);
  EXPECT_EQ(ze.at(1, 0, 0), 0.0);

  EXPECT_THROW(z_map(a, Image(2, 2)), std::invalid_argument);
  b.mean = Image(1, 1);
  EXPECT_THROW(z_map(a, b), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Tile tests

constexpr std::uint32_t kWidth = 64, kHeight = 48, kReplicates = 8;
constexpr double kSd = 0.5;

TEST(ImageStatisticsTiles, SameDistributionIsNotRejected) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 11, kSd);
  const std::vector<Image> b = normal_replicates(kWidth, kHeight, kReplicates, 12, kSd);
  const TileTestResult result = compare_tiles(a, b, kAlpha);
  EXPECT_EQ(result.tests, 8u * 6u * 3u);
  ASSERT_EQ(result.tiles.size(), result.tests);
  EXPECT_FALSE(result.rejected);
  EXPECT_GT(result.min_p_adjusted, 0.2);
  // Every tile is within 10x of the image mean, so all are bright.
  EXPECT_EQ(result.bright_tiles, result.tests);

  // The raw p-values of independent tiles are uniform when the means agree.
  std::vector<double> p;
  for (const TileTest& t : result.tiles) p.push_back(t.p_value);
  EXPECT_GT(ks_uniform(p).p_value, 0.01);

  // The detectable bias scales the standard error of the difference of two tile means, each the
  // mean of R tile averages of 64 pixels: sqrt(2 sd² / 64 / R); Welch's dof is at most 14.
  const double stderr_of_difference = std::sqrt(2.0 * kSd * kSd / 64.0 / kReplicates);
  const double expected =
      detectable_multiplier(kAlpha / result.tests, 2.0 * (kReplicates - 1)) * stderr_of_difference;
  double sum = 0.0, worst = 0.0;
  for (const TileTest& t : result.tiles) {
    EXPECT_LE(t.dof, 2.0 * (kReplicates - 1) + 1e-9);
    EXPECT_GE(t.dof, kReplicates - 1 - 1e-9);
    sum += t.min_detectable_bias;
    worst = std::max(worst, t.min_detectable_bias / (0.5 * (t.mean_a + t.mean_b)));
  }
  const double ratio = sum / result.tests / expected;
  EXPECT_GT(ratio, 0.9) << expected;
  EXPECT_LT(ratio, 1.3) << expected;
  EXPECT_DOUBLE_EQ(result.worst_bright_relative_mdb, worst);

  // Holm's adjusted p-values are at least the raw ones.
  for (const TileTest& t : result.tiles) EXPECT_GE(t.p_adjusted, t.p_value);
}

TEST(ImageStatisticsTiles, BiasOfTwiceTheDetectableIsFoundOnItsTile) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 21, kSd);
  std::vector<Image> b = normal_replicates(kWidth, kHeight, kReplicates, 22, kSd);
  const TileTestResult before = compare_tiles(a, b, kAlpha);
  ASSERT_FALSE(before.rejected);
  constexpr std::uint32_t kTx = 5, kTy = 2;
  for (std::uint32_t c = 0; c < kImageChannels; ++c) {
    const TileTest& t = find_tile(before, kTx, kTy, c);
    ASSERT_GT(t.min_detectable_bias, 0.0);
    add_to_tile(b, kTx, kTy, c, 2.0 * t.min_detectable_bias);
  }
  const TileTestResult after = compare_tiles(a, b, kAlpha);
  EXPECT_TRUE(after.rejected);
  const TileTest& smallest = smallest_p_adjusted(after);
  EXPECT_EQ(smallest.tile_x, kTx);
  EXPECT_EQ(smallest.tile_y, kTy);
  EXPECT_LE(smallest.p_adjusted, kAlpha);
  EXPECT_EQ(after.min_p_adjusted, smallest.p_adjusted);
  for (std::uint32_t c = 0; c < kImageChannels; ++c) {
    EXPECT_LE(find_tile(after, kTx, kTy, c).p_adjusted, kAlpha) << "channel " << c;
  }
}

// The samples factor: images whose noise is halved around the same means (what 4× the samples
// per pixel does to a standard error) halve the detectable bias, so the factor falls 4×, and
// the factor the noisier pair reports brings it to the requirement.
TEST(ImageStatisticsTiles, SamplesFactorPredictsTheRequiredPower) {
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
  ASSERT_GT(tile_samples_factor(mdb), 1.0);
  EXPECT_NEAR(tile_samples_factor(half), tile_samples_factor(mdb) / 4.0,
              1e-2 * tile_samples_factor(mdb));
  const double by = std::sqrt(tile_samples_factor(mdb));
  EXPECT_NEAR(compare_tiles(shrunk(a, by), shrunk(b, by), kAlpha).worst_bright_relative_mdb,
              kMaxBrightRelativeMdb, 1e-2 * kMaxBrightRelativeMdb);
}

TEST(ImageStatisticsTiles, AgainstExactImage) {
  const Image exact = truth(kWidth, kHeight);
  std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 31, kSd);
  const TileTestResult before = test_tiles_against_exact(a, exact, kAlpha);
  EXPECT_EQ(before.tests, 8u * 6u * 3u);
  EXPECT_FALSE(before.rejected);
  EXPECT_GT(before.min_p_adjusted, 0.2);
  std::vector<double> p;
  for (const TileTest& t : before.tiles) {
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
  const TileTestResult after = test_tiles_against_exact(a, exact, kAlpha);
  EXPECT_TRUE(after.rejected);
  const TileTest& smallest = smallest_p_adjusted(after);
  EXPECT_EQ(smallest.tile_x, kTx);
  EXPECT_EQ(smallest.tile_y, kTy);
  EXPECT_LT(smallest.statistic, 0.0);
}

// 20x12 in tiles of 8: 3x2 tiles, the right column 4 wide and the bottom row 4 high.
TEST(ImageStatisticsTiles, PartialEdgeTiles) {
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
  const TileTestResult same = compare_tiles(a, a, kAlpha);
  EXPECT_EQ(same.tests, 18u);
  ASSERT_EQ(same.tiles.size(), 18u);
  // Tiles in rows of tiles, channels within a tile.
  EXPECT_EQ(same.tiles[3].tile_x, 1u);
  EXPECT_EQ(same.tiles[3].channel, 0u);
  EXPECT_EQ(same.tiles[17].tile_x, 2u);
  EXPECT_EQ(same.tiles[17].tile_y, 1u);
  EXPECT_EQ(same.tiles[17].channel, 2u);
  // Corner tile: x 16..19, y 8..11; replicates 0, 1, 2 average to 1.
  const TileTest& corner = find_tile(same, 2, 1, 2);
  EXPECT_DOUBLE_EQ(corner.mean_a, 17.5 + 950.0 + 1.0 + 2000.0);
  EXPECT_DOUBLE_EQ(corner.mean_b, corner.mean_a);
  EXPECT_DOUBLE_EQ(find_tile(same, 2, 0, 0).mean_a, 17.5 + 350.0 + 1.0);  // y 0..7
  EXPECT_DOUBLE_EQ(find_tile(same, 0, 1, 0).mean_a, 3.5 + 950.0 + 1.0);   // x 0..7
  for (const TileTest& t : same.tiles) EXPECT_EQ(t.p_value, 1.0);
  EXPECT_FALSE(same.rejected);

  // Against the exact mean image (each pixel's average over the replicates): the tile means of
  // the replicates spread by 1 around it.
  Image exact = a[1];
  const TileTestResult against = test_tiles_against_exact(a, exact, kAlpha);
  EXPECT_EQ(against.tests, 18u);
  EXPECT_DOUBLE_EQ(find_tile(against, 2, 1, 0).mean_b, 17.5 + 950.0 + 1.0);
  EXPECT_NEAR(find_tile(against, 2, 1, 0).p_value, 1.0, 1e-12);

  // A 4-pixel tile size on the same image: 5x3 tiles, none partial.
  EXPECT_EQ(compare_tiles(a, a, kAlpha, {.tile = 4}).tests, 45u);
  // A tile larger than the image: one tile per channel.
  EXPECT_EQ(compare_tiles(a, a, kAlpha, {.tile = 64}).tests, 3u);
  // The two sides may have different replicate counts.
  EXPECT_FALSE(compare_tiles(a, std::span(a).first(2), kAlpha).rejected);
}

TEST(ImageStatisticsTiles, ConstantReplicatesAreTestedExactly) {
  const std::vector<Image> a(2, truth(10, 10));
  std::vector<Image> b = a;
  const TileTestResult same = compare_tiles(a, b, kAlpha);
  EXPECT_EQ(same.tests, 12u);
  EXPECT_FALSE(same.rejected);
  EXPECT_EQ(same.min_p_adjusted, 1.0);
  for (const TileTest& t : same.tiles) {
    EXPECT_EQ(t.p_value, 1.0);
    EXPECT_EQ(t.min_detectable_bias, 0.0);
  }
  EXPECT_EQ(same.worst_bright_relative_mdb, 0.0);
  add_to_tile(b, 1, 0, 2, 1e-9);
  const TileTestResult differ = compare_tiles(a, b, kAlpha);
  EXPECT_TRUE(differ.rejected);
  EXPECT_EQ(find_tile(differ, 1, 0, 2).p_value, 0.0);
  EXPECT_EQ(find_tile(differ, 1, 0, 2).statistic, -kInf);
  EXPECT_EQ(find_tile(differ, 1, 0, 1).p_value, 1.0);
}

TEST(ImageStatisticsTiles, NonFiniteValueIsRejected) {
  const std::vector<Image> a = normal_replicates(16, 16, 4, 41, kSd);
  std::vector<Image> b = normal_replicates(16, 16, 4, 42, kSd);
  b[2].at(9, 3, 1) = std::nan("");
  const TileTestResult result = compare_tiles(a, b, kAlpha);
  EXPECT_TRUE(result.rejected);
  EXPECT_EQ(result.min_p_adjusted, 0.0);
  const TileTest& bad = find_tile(result, 1, 0, 1);
  EXPECT_EQ(bad.p_value, 0.0);
  EXPECT_TRUE(std::isnan(bad.min_detectable_bias));
  EXPECT_GT(find_tile(result, 0, 0, 1).p_value, 0.0);
}

TEST(ImageStatisticsTiles, BrightTilesAndTheirPower) {
  // Black except one bright tile: only that one is bright (0 is never bright), and its relative
  // detectable bias is its detectable bias over its mean.
  std::vector<Image> a(4, Image(16, 8)), b(4, Image(16, 8));
  for (std::uint32_t r = 0; r < 4; ++r) {
    a[r].at(9, 2, 0) = 10.0 + r;
    b[r].at(9, 2, 0) = 10.0 + 2.0 * r;
  }
  const TileTestResult result = compare_tiles(a, b, kAlpha);
  EXPECT_EQ(result.bright_tiles, 1u);
  const TileTest& bright = find_tile(result, 1, 0, 0);
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
  const TileTestResult lower = compare_tiles(a, b, kAlpha, {.power = 0.5});
  EXPECT_LT(find_tile(lower, 1, 0, 0).min_detectable_bias, bright.min_detectable_bias);
  // Decided in a family of 40 verdicts, the tile is held to alpha / (40 × 6): the detectable bias
  // is computed at that share, and the reported share says so.
  const TileTestResult in_family = compare_tiles(a, b, kAlpha, {.family_size = 40});
  EXPECT_DOUBLE_EQ(in_family.detection_share, kAlpha / 240.0);
  EXPECT_DOUBLE_EQ(result.detection_share, kAlpha / 6.0);
  EXPECT_DOUBLE_EQ(find_tile(in_family, 1, 0, 0).min_detectable_bias,
                   detectable_multiplier(kAlpha / 240.0, welch.dof) * welch.stderr_of_difference);
  EXPECT_GT(in_family.worst_bright_relative_mdb, result.worst_bright_relative_mdb);
  // The decision of the comparison alone is unchanged; only the power statement moves.
  EXPECT_EQ(in_family.min_p_adjusted, result.min_p_adjusted);
}

// The self-check's target: the tile and channel with the largest mean of a.
TEST(ImageStatisticsTiles, BrightestTile) {
  std::vector<Image> a(2, Image(16, 8)), b(2, Image(16, 8));
  a[0].at(3, 5, 2) = 7.0;
  a[1].at(3, 5, 2) = 9.0;
  const TileTestResult result = compare_tiles(a, b, kAlpha);
  const TileTest& brightest = brightest_tile(result);
  EXPECT_EQ(brightest.tile_x, 0u);
  EXPECT_EQ(brightest.tile_y, 0u);
  EXPECT_EQ(brightest.channel, 2u);
  EXPECT_THROW(brightest_tile(TileTestResult{}), std::invalid_argument);
}

TEST(ImageStatisticsTiles, RejectsBadArguments) {
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
// summarize_z

TEST(ImageStatisticsSummary, GuardsAndExpectedCount) {
  std::vector<Image> a(3, Image(3, 2)), b(5, Image(3, 2));
  for (Image& image : a) image.at(0, 0, 1) = 1.0;  // b all 0 there: low count
  b[4].at(2, 1, 0) = 3.0;                          // a all 0 there: low count
  a[0].at(1, 1, 2) = 1.0, b[0].at(1, 1, 2) = 1.0;  // both sample it
  Image z(3, 2);
  z.at(1, 0, 0) = -4.5;
  z.at(1, 0, 1) = 4.2;  // same pixel: counted once
  z.at(2, 0, 2) = 3.9;
  z.at(0, 1, 0) = kInf;
  const PixelTestSummary s = summarize_z(z, a, b);
  EXPECT_EQ(s.max_abs_z, kInf);
  EXPECT_EQ(s.pixels_beyond_4_sigma, 2u);
  EXPECT_EQ(s.low_count_pixels, 2u);
  // The smaller side has 3 replicates: 2 dof.
  EXPECT_DOUBLE_EQ(s.expected_beyond_4_sigma, 6.0 * 3.0 * student_t_p_value(4.0, 2.0));

  // Against an exact image: b is that one image, and the dof are a's.
  Image exact(3, 2);
  exact.at(0, 0, 1) = 1.0;
  exact.at(2, 0, 0) = 0.5;  // a all 0 there
  z.at(0, 1, 0) = std::nan("");
  const PixelTestSummary e = summarize_z(z, a, std::span(&exact, 1));
  EXPECT_TRUE(std::isnan(e.max_abs_z));
  EXPECT_EQ(e.low_count_pixels, 2u);  // (2, 0) and (1, 1)
  EXPECT_DOUBLE_EQ(e.expected_beyond_4_sigma, 6.0 * 3.0 * student_t_p_value(4.0, 2.0));

  EXPECT_THROW(summarize_z(z, std::span(a).first(1), b), std::invalid_argument);
  EXPECT_THROW(summarize_z(z, a, std::vector<Image>{}), std::invalid_argument);
  EXPECT_THROW(summarize_z(Image(2, 2), a, b), std::invalid_argument);
}

TEST(ImageStatisticsSummary, NullSamplesStayBelowTheBound) {
  const std::vector<Image> a = normal_replicates(kWidth, kHeight, kReplicates, 51, kSd);
  const std::vector<Image> b = normal_replicates(kWidth, kHeight, kReplicates, 52, kSd);
  const Image z = z_map(pixel_statistics(a), pixel_statistics(b));
  const PixelTestSummary s = summarize_z(z, a, b);
  EXPECT_EQ(s.low_count_pixels, 0u);
  EXPECT_GT(s.max_abs_z, 2.0);
  EXPECT_LE(s.pixels_beyond_4_sigma, 2.0 * s.expected_beyond_4_sigma + 3.0);
}

// ---------------------------------------------------------------------------------------------
// EXR files

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(ExrFile, RoundTripIsBitwise) {
  TemporaryFolder folder;
  const std::filesystem::path file = folder.path() / "image.exr";
  constexpr std::uint32_t kW = 7, kH = 5;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> uniform(-1e6f, 1e6f);
  std::vector<ExrChannel> channels = {{"R", {}}, {"G", {}}, {"B", {}}, {"z", {}}};
  for (ExrChannel& channel : channels) {
    for (std::uint32_t i = 0; i < kW * kH; ++i) channel.values.push_back(uniform(rng));
  }
  // Values a lossy or half-float path would change.
  channels[3].values[0] = std::numeric_limits<float>::denorm_min();
  channels[3].values[1] = -0.0f;
  channels[3].values[2] = std::numeric_limits<float>::infinity();
  channels[3].values[3] = std::numeric_limits<float>::quiet_NaN();
  channels[3].values[4] = std::numeric_limits<float>::max();
  channels[3].values[5] = 1.0f + std::numeric_limits<float>::epsilon();
  write_exr(file, kW, kH, channels);
  EXPECT_EQ(files_under(folder.path()), std::vector<std::string>{"image.exr"});

  std::uint32_t width = 0, height = 0;
  const std::vector<ExrChannel> back = read_exr(file, width, height);
  EXPECT_EQ(width, kW);
  EXPECT_EQ(height, kH);
  ASSERT_EQ(back.size(), channels.size());
  for (const ExrChannel& written : channels) {
    const auto read = std::find_if(back.begin(), back.end(),
                                   [&](const ExrChannel& c) { return c.name == written.name; });
    ASSERT_NE(read, back.end()) << written.name;
    EXPECT_TRUE(same_bits(read->values, written.values)) << written.name;
  }

  // Writing again replaces the file.
  channels.resize(1);
  write_exr(file, kW, kH, channels);
  EXPECT_EQ(read_exr(file, width, height).size(), 1u);
  EXPECT_EQ(files_under(folder.path()), std::vector<std::string>{"image.exr"});
}

TEST(ExrFile, RgbImageRowMajorTopRowFirst) {
  TemporaryFolder folder;
  const std::filesystem::path file = folder.path() / "rgb.exr";
  Image image(3, 2);
  for (std::uint32_t y = 0; y < 2; ++y) {
    for (std::uint32_t x = 0; x < 3; ++x) {
      for (std::uint32_t c = 0; c < kImageChannels; ++c) {
        image.at(x, y, c) = 0.1 + x + 10.0 * y + 100.0 * c;
      }
    }
  }
  write_exr_rgb(file, image);
  std::uint32_t width = 0, height = 0;
  const std::vector<ExrChannel> back = read_exr(file, width, height);
  EXPECT_EQ(width, 3u);
  EXPECT_EQ(height, 2u);
  ASSERT_EQ(back.size(), 3u);
  const char* names = "RGB";
  for (std::uint32_t c = 0; c < kImageChannels; ++c) {
    const auto read = std::find_if(back.begin(), back.end(), [&](const ExrChannel& channel) {
      return channel.name == std::string(1, names[c]);
    });
    ASSERT_NE(read, back.end());
    for (std::uint32_t y = 0; y < 2; ++y) {
      for (std::uint32_t x = 0; x < 3; ++x) {
        EXPECT_EQ(read->values[y * 3 + x], static_cast<float>(image.at(x, y, c)));
      }
    }
  }
}

TEST(ExrFile, ExrheaderSeesFloatChannels) {
  const std::filesystem::path exrheader = "/usr/bin/exrheader";
  if (!std::filesystem::exists(exrheader)) {
    GTEST_SKIP() << "no " << exrheader << " (Debian package openexr)";
  }
  TemporaryFolder folder;
  const std::filesystem::path file = folder.path() / "rgb.exr";
  const std::filesystem::path listing = folder.path() / "header.txt";
  write_exr_rgb(file, Image(4, 3));
  const std::string command =
      exrheader.string() + " '" + file.string() + "' > '" + listing.string() + "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(listing);
  const std::string header = read_text(listing);
  EXPECT_NE(header.find("zip"), std::string::npos) << header;
  for (const char* channel : {"R", "G", "B"}) {
    EXPECT_NE(header.find(std::string(channel) + ", 32-bit floating-point"), std::string::npos)
        << header;
  }
  EXPECT_EQ(header.find("16-bit"), std::string::npos) << header;
}

TEST(ExrFile, FailuresThrowAndLeaveNoTemporary) {
  TemporaryFolder folder;
  const std::vector<ExrChannel> one = {{"Y", std::vector<float>(6, 1.0f)}};
  EXPECT_THROW(write_exr(folder.path() / "missing" / "a.exr", 3, 2, one), std::runtime_error);
  // The rename onto a folder fails after the temporary was written.
  std::filesystem::create_directory(folder.path() / "taken.exr");
  EXPECT_THROW(write_exr(folder.path() / "taken.exr", 3, 2, one), std::runtime_error);
  EXPECT_EQ(files_under(folder.path()), std::vector<std::string>{});

  EXPECT_THROW(write_exr(folder.path() / "a.exr", 2, 2, one), std::invalid_argument);
  EXPECT_THROW(write_exr(folder.path() / "a.exr", 0, 2, {{"Y", {}}}), std::invalid_argument);
  EXPECT_THROW(write_exr(folder.path() / "a.exr", 3, 2, {}), std::invalid_argument);
  EXPECT_THROW(write_exr(folder.path() / "a.exr", 3, 2, {one[0], one[0]}), std::invalid_argument);
  EXPECT_EQ(files_under(folder.path()), std::vector<std::string>{});

  std::uint32_t width = 0, height = 0;
  EXPECT_THROW(read_exr(folder.path() / "none.exr", width, height), std::runtime_error);
  write_text(folder.path() / "text.exr", "not an EXR file");
  EXPECT_THROW(read_exr(folder.path() / "text.exr", width, height), std::runtime_error);
}

}  // namespace
}  // namespace pcbench
