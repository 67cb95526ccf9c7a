#include "harness/verify/image_statistics.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "harness/run/tally.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

void check_image(const Image& image, const Image& first) {
  if (image.values.size() != image.pixel_count() * kImageChannels) {
    throw std::invalid_argument(fmt::format("a {}x{} image holds {} values", image.width,
                                            image.height, image.values.size()));
  }
  if (image.width != first.width || image.height != first.height) {
    throw std::invalid_argument(fmt::format("images of different sizes: {}x{} and {}x{}",
                                            first.width, first.height, image.width, image.height));
  }
}

// Every replicate the size of `like`, or of the first replicate.
void check_replicates(std::span<const Image> images, const Image* like = nullptr) {
  if (images.size() < 2) {
    throw std::invalid_argument(
        fmt::format("{} replicate image(s): a standard error needs at least 2", images.size()));
  }
  for (const Image& image : images) check_image(image, like != nullptr ? *like : images.front());
}

// (mean_a - mean_b) / sqrt(variance), without the NaN of 0/0: two values known exactly are
// either equal (z = 0) or certainly different (±inf).
double z_score(double mean_a, double mean_b, double variance) {
  const double difference = mean_a - mean_b;
  if (variance == 0.0) return difference == 0.0 ? 0.0 : std::copysign(kInf, difference);
  return difference / std::sqrt(variance);
}

// Tiles of t x t pixels from the top left; w and h are not 0.
struct Tiling {
  std::uint32_t width, height, tile, tiles_x, tiles_y;
  Tiling(std::uint32_t w, std::uint32_t h, std::uint32_t t)
      : width(w), height(h), tile(t), tiles_x((w - 1) / t + 1), tiles_y((h - 1) / t + 1) {}
  std::size_t count() const { return std::size_t{tiles_x} * tiles_y; }
  // Edge tiles are cut by the image's border.
  double pixels(std::uint32_t tx, std::uint32_t ty) const {
    return static_cast<double>(std::min(tile, width - tx * tile)) *
           static_cast<double>(std::min(tile, height - ty * tile));
  }
};

// Each image's mean of each tile and channel, at [(tile * 3 + channel) * R + replicate]: one
// tile's R observations are contiguous, a span for the tests.
std::vector<double> tile_means(std::span<const Image> images, const Tiling& tiling) {
  const std::size_t count = images.size();
  std::vector<double> means(tiling.count() * kImageChannels * count, 0.0);
  std::vector<double> sums(tiling.count() * kImageChannels);
  for (std::size_t r = 0; r < count; ++r) {
    std::fill(sums.begin(), sums.end(), 0.0);
    for (std::uint32_t y = 0; y < tiling.height; ++y) {
      const std::size_t row = std::size_t{y / tiling.tile} * tiling.tiles_x;
      for (std::uint32_t x = 0; x < tiling.width; ++x) {
        const std::size_t tile = row + x / tiling.tile;
        for (std::uint32_t c = 0; c < kImageChannels; ++c) {
          sums[tile * kImageChannels + c] += images[r].at(x, y, c);
        }
      }
    }
    for (std::uint32_t ty = 0; ty < tiling.tiles_y; ++ty) {
      for (std::uint32_t tx = 0; tx < tiling.tiles_x; ++tx) {
        const std::size_t tile = std::size_t{ty} * tiling.tiles_x + tx;
        for (std::uint32_t c = 0; c < kImageChannels; ++c) {
          const std::size_t k = tile * kImageChannels + c;
          means[k * count + r] = sums[k] / tiling.pixels(tx, ty);
        }
      }
    }
  }
  return means;
}

void check_options(double alpha, const TileOptions& options) {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    throw std::invalid_argument(fmt::format("alpha {} is not in (0, 1)", alpha));
  }
  if (options.tile == 0) throw std::invalid_argument("tile size 0");
  if (!(options.power > 0.0 && options.power < 1.0)) {
    throw std::invalid_argument(fmt::format("power {} is not in (0, 1)", options.power));
  }
  if (options.family_size == 0) throw std::invalid_argument("family size 0");
}

// From the raw test of each tile and channel (in the order of tile_means): Holm over all of
// them, the minimum detectable bias at the share of alpha that decides (TileOptions::
// family_size), and which tiles are bright.
TileTestResult decide_tiles(const std::vector<TwoSampleTest>& raw, const Tiling& tiling,
                            double alpha, const TileOptions& options) {
  TileTestResult out;
  out.tests = static_cast<std::uint32_t>(raw.size());
  const double share =
      alpha / (static_cast<double>(options.family_size) * static_cast<double>(raw.size()));
  out.detection_share = share;

  // The image mean of each channel, over a and b alike, as the tile means are.
  std::array<double, kImageChannels> image_mean = {};
  for (std::size_t k = 0; k < raw.size(); ++k) {
    const std::size_t tile = k / kImageChannels;
    const double pixels = tiling.pixels(static_cast<std::uint32_t>(tile % tiling.tiles_x),
                                        static_cast<std::uint32_t>(tile / tiling.tiles_x));
    image_mean[k % kImageChannels] += pixels * 0.5 * (raw[k].mean_a + raw[k].mean_b);
  }
  for (double& mean : image_mean) {
    mean /= static_cast<double>(tiling.width) * static_cast<double>(tiling.height);
  }

  std::vector<double> p_values(raw.size());
  out.tiles.resize(raw.size());
  for (std::size_t k = 0; k < raw.size(); ++k) {
    const TwoSampleTest& test = raw[k];
    TileTest& t = out.tiles[k];
    const std::size_t tile = k / kImageChannels;
    t.tile_x = static_cast<std::uint32_t>(tile % tiling.tiles_x);
    t.tile_y = static_cast<std::uint32_t>(tile / tiling.tiles_x);
    t.channel = static_cast<std::uint32_t>(k % kImageChannels);
    t.mean_a = test.mean_a;
    t.mean_b = test.mean_b;
    t.statistic = test.statistic;
    t.dof = test.dof;
    // A non-finite pixel makes the tile's test NaN; it is a defect, so it counts as rejected
    // (Holm's ordering needs numbers, too).
    const bool finite = std::isfinite(test.mean_a) && std::isfinite(test.mean_b);
    t.p_value = finite && !std::isnan(test.p_value) ? test.p_value : 0.0;
    p_values[k] = t.p_value;
    // A tile known exactly on both sides detects any bias; otherwise the t quantiles need a dof.
    if (test.stderr_of_difference == 0.0) {
      t.min_detectable_bias = 0.0;
    } else if (finite && test.dof > 0.0 && std::isfinite(test.stderr_of_difference)) {
      t.min_detectable_bias =
          detectable_multiplier(share, test.dof, options.power) * test.stderr_of_difference;
    } else {
      t.min_detectable_bias = kNaN;
    }
    const double tile_mean = 0.5 * (test.mean_a + test.mean_b);
    // A tile mean of 0 has no relative bias to speak of, even in a black channel.
    t.bright = tile_mean > 0.0 && tile_mean >= options.bright_fraction * image_mean[t.channel];
    if (t.bright) {
      ++out.bright_tiles;
      const double relative = t.min_detectable_bias / tile_mean;
      // NaN sticks: an unknown power must not read as enough.
      if (std::isnan(relative) || std::isnan(out.worst_bright_relative_mdb)) {
        out.worst_bright_relative_mdb = kNaN;
      } else {
        out.worst_bright_relative_mdb = std::max(out.worst_bright_relative_mdb, relative);
      }
    }
  }

  const std::vector<double> adjusted = holm_adjusted(p_values);
  for (std::size_t k = 0; k < raw.size(); ++k) {
    out.tiles[k].p_adjusted = adjusted[k];
    out.min_p_adjusted = std::min(out.min_p_adjusted, adjusted[k]);
  }
  out.rejected = out.min_p_adjusted <= alpha;
  return out;
}

}  // namespace

std::vector<double> relative_error_scale(const Image& reference) {
  double mean = 0.0;
  for (double v : reference.values) mean += v;
  mean /= static_cast<double>(std::max<std::size_t>(1, reference.values.size()));
  std::vector<double> scale(reference.values.size());
  for (std::size_t i = 0; i < scale.size(); ++i) {
    scale[i] = reference.values[i] + kRelativeErrorFloor * mean;
  }
  return scale;
}

double relative_variance(const Image& mean, const Image& standard_error) {
  const std::vector<double> scale = relative_error_scale(mean);
  double sum = 0.0;
  for (std::size_t i = 0; i < scale.size(); ++i) {
    const double r = scale[i] > 0.0 ? standard_error.values[i] / scale[i] : 0.0;
    sum += r * r;
  }
  return scale.empty() ? 0.0 : sum / static_cast<double>(scale.size());
}

PixelStatistics pixel_statistics(std::span<const Image> replicates) {
  check_replicates(replicates);
  const Image& first = replicates.front();
  PixelStatistics out{.mean = Image(first.width, first.height),
                      .standard_error = Image(first.width, first.height),
                      .replicates = static_cast<std::uint32_t>(replicates.size())};
  const double count = static_cast<double>(replicates.size());
  for (std::size_t i = 0; i < first.values.size(); ++i) {
    // The runs' own tally (compensated mean, Welford variance, non-finite values propagate);
    // no largest values are kept.
    Tally tally(0);
    for (std::size_t r = 0; r < replicates.size(); ++r) tally.add(replicates[r].values[i], r);
    out.mean.values[i] = tally.mean();
    out.standard_error.values[i] = std::sqrt(tally.variance() / count);
  }
  return out;
}

Image z_map(const PixelStatistics& a, const PixelStatistics& b) {
  check_image(a.standard_error, a.mean);
  check_image(b.mean, a.mean);
  check_image(b.standard_error, a.mean);
  Image z(a.mean.width, a.mean.height);
  for (std::size_t i = 0; i < z.values.size(); ++i) {
    const double se_a = a.standard_error.values[i], se_b = b.standard_error.values[i];
    z.values[i] = z_score(a.mean.values[i], b.mean.values[i], se_a * se_a + se_b * se_b);
  }
  return z;
}

Image z_map(const PixelStatistics& a, const Image& exact) {
  check_image(a.standard_error, a.mean);
  check_image(exact, a.mean);
  Image z(a.mean.width, a.mean.height);
  for (std::size_t i = 0; i < z.values.size(); ++i) {
    const double se = a.standard_error.values[i];
    z.values[i] = z_score(a.mean.values[i], exact.values[i], se * se);
  }
  return z;
}

TileTestResult compare_tiles(std::span<const Image> a, std::span<const Image> b, double alpha,
                             const TileOptions& options) {
  check_options(alpha, options);
  check_replicates(a);
  check_replicates(b, &a.front());
  if (a.front().pixel_count() == 0) throw std::invalid_argument("empty image");
  const Tiling tiling(a.front().width, a.front().height, options.tile);
  const std::vector<double> means_a = tile_means(a, tiling), means_b = tile_means(b, tiling);
  std::vector<TwoSampleTest> raw(tiling.count() * kImageChannels);
  for (std::size_t k = 0; k < raw.size(); ++k) {
    raw[k] = welch_two_sample(std::span(means_a).subspan(k * a.size(), a.size()),
                              std::span(means_b).subspan(k * b.size(), b.size()));
  }
  return decide_tiles(raw, tiling, alpha, options);
}

namespace {

// One-sample tests of a's replicate tile means against a reference's tile means, whose variance
// is `reference_variance` per tile and channel (empty: exact).
TileTestResult tiles_against(std::span<const Image> a, const Image& reference,
                             const std::vector<double>& reference_variance, double alpha,
                             const TileOptions& options) {
  const Tiling tiling(reference.width, reference.height, options.tile);
  const std::vector<double> means_a = tile_means(a, tiling);
  const std::vector<double> means_reference = tile_means(std::span(&reference, 1), tiling);
  const double count = static_cast<double>(a.size());
  std::vector<TwoSampleTest> raw(tiling.count() * kImageChannels);
  for (std::size_t k = 0; k < raw.size(); ++k) {
    Tally tally(0);
    for (std::size_t r = 0; r < a.size(); ++r) tally.add(means_a[k * a.size() + r], r);
    const double variance = reference_variance.empty() ? 0.0 : reference_variance[k];
    raw[k] = welch_test(tally.mean(), tally.variance() / count, count - 1.0, means_reference[k],
                        variance, kInf);
    // Welch's test with an exactly known b (variance 0, infinite dof) is Student's one-sample
    // test; its dof is R - 1 also where a does not vary (Welch would add b's infinity).
    if (variance == 0.0) raw[k].dof = count - 1.0;
  }
  return decide_tiles(raw, tiling, alpha, options);
}

}  // namespace

TileTestResult test_tiles_against_exact(std::span<const Image> a, const Image& exact, double alpha,
                                        const TileOptions& options) {
  check_options(alpha, options);
  check_replicates(a);
  check_image(exact, a.front());
  if (exact.pixel_count() == 0) throw std::invalid_argument("empty image");
  return tiles_against(a, exact, {}, alpha, options);
}

TileTestResult test_tiles_against_reference(std::span<const Image> a, const Image& reference,
                                            const Image& reference_stderr, double alpha,
                                            const TileOptions& options) {
  check_options(alpha, options);
  check_replicates(a);
  check_image(reference, a.front());
  check_image(reference_stderr, a.front());
  if (reference.pixel_count() == 0) throw std::invalid_argument("empty image");
  const Tiling tiling(reference.width, reference.height, options.tile);
  // A tile mean's variance: the sum of its pixels' variances over the pixel count squared.
  Image squared = reference_stderr;
  for (double& v : squared.values) v *= v;
  std::vector<double> variance = tile_means(std::span(&squared, 1), tiling);
  for (std::size_t k = 0; k < variance.size(); ++k) {
    const std::size_t tile = k / kImageChannels;
    variance[k] /= tiling.pixels(static_cast<std::uint32_t>(tile % tiling.tiles_x),
                                 static_cast<std::uint32_t>(tile / tiling.tiles_x));
  }
  return tiles_against(a, reference, variance, alpha, options);
}

PixelTestSummary summarize_z(const Image& z, std::span<const Image> a, std::span<const Image> b) {
  check_image(z, z);
  check_replicates(a, &z);
  if (b.empty()) throw std::invalid_argument("no other side to compare with");
  for (const Image& image : b) check_image(image, z);
  const bool exact = b.size() == 1;
  PixelTestSummary out;
  bool any_nan = false;
  const auto all_zero = [](std::span<const Image> images, std::size_t i) {
    return std::all_of(images.begin(), images.end(),
                       [i](const Image& image) { return image.values[i] == 0.0; });
  };
  for (std::size_t p = 0; p < z.pixel_count(); ++p) {
    bool beyond = false, low_count = false;
    for (std::uint32_t c = 0; c < kImageChannels; ++c) {
      const std::size_t i = p * kImageChannels + c;
      const double magnitude = std::fabs(z.values[i]);
      if (std::isnan(magnitude)) any_nan = true;
      out.max_abs_z = std::max(out.max_abs_z, magnitude);
      beyond = beyond || magnitude > 4.0;
      low_count = low_count || all_zero(a, i) != all_zero(b, i);
    }
    out.pixels_beyond_4_sigma += beyond ? 1 : 0;
    out.low_count_pixels += low_count ? 1 : 0;
  }
  if (any_nan) out.max_abs_z = kNaN;
  const std::size_t smaller = exact ? a.size() : std::min(a.size(), b.size());
  const double tail = student_t_p_value(4.0, static_cast<double>(smaller) - 1.0);
  out.expected_beyond_4_sigma = static_cast<double>(z.pixel_count()) * std::min(1.0, 3.0 * tail);
  return out;
}

}  // namespace pcbench
