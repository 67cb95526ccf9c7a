#include "harness/verify/block_pyramid.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "base/tally.h"
#include "harness/verify/image_statistics.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

void check_options(double alpha, const PyramidOptions& options) {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    throw std::invalid_argument(fmt::format("alpha {} is not in (0, 1)", alpha));
  }
  if (options.tile == 0) throw std::invalid_argument("tile size 0");
  if (!(options.power > 0.0 && options.power < 1.0)) {
    throw std::invalid_argument(fmt::format("power {} is not in (0, 1)", options.power));
  }
  if (options.family_size == 0) throw std::invalid_argument("family size 0");
}

// Blocks of b × b pixels from the top left; w and h are not 0.
struct Blocking {
  std::uint32_t width, height, block, columns, rows;
  Blocking(std::uint32_t w, std::uint32_t h, std::uint32_t b)
      : width(w), height(h), block(b), columns((w - 1) / b + 1), rows((h - 1) / b + 1) {}
  std::size_t count() const { return std::size_t{columns} * rows; }
  // Edge blocks are cut by the image's border.
  double pixels(std::uint32_t bx, std::uint32_t by) const {
    return static_cast<double>(std::min(block, width - bx * block)) *
           static_cast<double>(std::min(block, height - by * block));
  }
  double pixels(std::size_t index) const {
    return pixels(static_cast<std::uint32_t>(index % columns),
                  static_cast<std::uint32_t>(index / columns));
  }
};

std::vector<Blocking> pyramid(const Image& like, const PyramidOptions& options) {
  std::vector<Blocking> out;
  for (std::uint32_t block :
       pyramid_block_sizes(like.width, like.height, options.tile, options.max_scales)) {
    out.emplace_back(like.width, like.height, block);
  }
  return out;
}

// Each image's mean of each block and channel at every scale: out[s] at
// [(block * 3 + channel) * R + replicate], so that one block's R observations are contiguous, a
// span for the tests. The finest blocks sum their pixels row by row; a coarser block sums the
// (up to) four blocks it holds one scale down.
std::vector<std::vector<double>> block_means(std::span<const Image> images,
                                             const std::vector<Blocking>& scales) {
  const std::size_t count = images.size();
  std::vector<std::vector<double>> means(scales.size());
  std::vector<std::vector<double>> sums(scales.size());
  for (std::size_t s = 0; s < scales.size(); ++s) {
    means[s].assign(scales[s].count() * kImageChannels * count, 0.0);
    sums[s].resize(scales[s].count() * kImageChannels);
  }
  const Blocking& tiles = scales.front();
  for (std::size_t r = 0; r < count; ++r) {
    std::fill(sums[0].begin(), sums[0].end(), 0.0);
    for (std::uint32_t y = 0; y < tiles.height; ++y) {
      const std::size_t row = std::size_t{y / tiles.block} * tiles.columns;
      for (std::uint32_t x = 0; x < tiles.width; ++x) {
        const std::size_t tile = row + x / tiles.block;
        for (std::uint32_t c = 0; c < kImageChannels; ++c) {
          sums[0][tile * kImageChannels + c] += images[r].at(x, y, c);
        }
      }
    }
    for (std::size_t s = 1; s < scales.size(); ++s) {
      const Blocking& fine = scales[s - 1];
      const Blocking& coarse = scales[s];
      std::fill(sums[s].begin(), sums[s].end(), 0.0);
      for (std::uint32_t fy = 0; fy < fine.rows; ++fy) {
        for (std::uint32_t fx = 0; fx < fine.columns; ++fx) {
          const std::size_t from = std::size_t{fy} * fine.columns + fx;
          const std::size_t to = std::size_t{fy / 2} * coarse.columns + fx / 2;
          for (std::uint32_t c = 0; c < kImageChannels; ++c) {
            sums[s][to * kImageChannels + c] += sums[s - 1][from * kImageChannels + c];
          }
        }
      }
    }
    for (std::size_t s = 0; s < scales.size(); ++s) {
      for (std::size_t k = 0; k < sums[s].size(); ++k) {
        means[s][k * count + r] = sums[s][k] / scales[s].pixels(k / kImageChannels);
      }
    }
  }
  return means;
}

// One block test from its raw two-sample test, before the pyramid's correction.
BlockTest block_test(const TwoSampleTest& test, const Blocking& blocking, std::size_t k,
                     double share, double bright_threshold, double power) {
  BlockTest t;
  const std::size_t block = k / kImageChannels;
  t.x = static_cast<std::uint32_t>(block % blocking.columns);
  t.y = static_cast<std::uint32_t>(block / blocking.columns);
  t.channel = static_cast<std::uint32_t>(k % kImageChannels);
  t.mean_a = test.mean_a;
  t.mean_b = test.mean_b;
  t.statistic = test.statistic;
  t.dof = test.dof;
  // A non-finite pixel makes the block's test NaN; it is a defect, so it counts as rejected
  // (Holm's ordering needs numbers, too).
  const bool finite = std::isfinite(test.mean_a) && std::isfinite(test.mean_b);
  t.p_value = finite && !std::isnan(test.p_value) ? test.p_value : 0.0;
  // A block known exactly on both sides detects any bias; otherwise the t quantiles need a dof.
  if (test.stderr_of_difference == 0.0) {
    t.min_detectable_bias = 0.0;
  } else if (finite && test.dof > 0.0 && std::isfinite(test.stderr_of_difference)) {
    t.min_detectable_bias =
        detectable_multiplier(share, test.dof, power) * test.stderr_of_difference;
  } else {
    t.min_detectable_bias = kNaN;
  }
  const double block_mean = 0.5 * (test.mean_a + test.mean_b);
  // A block mean of 0 has no relative bias to speak of, even in a black channel.
  t.bright = block_mean > 0.0 && block_mean >= bright_threshold;
  return t;
}

// From the raw test of each block and channel at each scale (in the order of block_means): the
// weighted Holm procedure over the pyramid, the minimum detectable bias at the share of alpha
// that decides (PyramidOptions::family_size), and which blocks are bright.
PyramidResult decide_pyramid(const std::vector<std::vector<TwoSampleTest>>& raw,
                             const std::vector<Blocking>& scales, double alpha,
                             const PyramidOptions& options) {
  // The image mean of each channel, over a and b alike, as the block means are: from the tiles.
  std::array<double, kImageChannels> image_mean = {};
  const Blocking& tiles = scales.front();
  for (std::size_t k = 0; k < raw.front().size(); ++k) {
    image_mean[k % kImageChannels] +=
        tiles.pixels(k / kImageChannels) * 0.5 * (raw.front()[k].mean_a + raw.front()[k].mean_b);
  }
  for (double& mean : image_mean) {
    mean /= static_cast<double>(tiles.width) * static_cast<double>(tiles.height);
  }

  PyramidResult out;
  std::vector<double> p_values, weights;
  const double levels = static_cast<double>(scales.size());
  for (std::size_t s = 0; s < scales.size(); ++s) {
    ScaleTests scale{
        .block = scales[s].block, .columns = scales[s].columns, .rows = scales[s].rows};
    const double tests = static_cast<double>(raw[s].size());
    scale.detection_share = alpha / (static_cast<double>(options.family_size) * levels * tests);
    std::vector<double> relatives;
    for (std::size_t k = 0; k < raw[s].size(); ++k) {
      BlockTest t =
          block_test(raw[s][k], scales[s], k, scale.detection_share,
                     options.bright_fraction * image_mean[k % kImageChannels], options.power);
      if (t.bright) {
        ++scale.bright_tests;
        const double relative = t.min_detectable_bias / (0.5 * (t.mean_a + t.mean_b));
        relatives.push_back(relative);
        // NaN sticks: an unknown power must not read as enough.
        if (std::isnan(relative) || std::isnan(scale.worst_bright_relative_mdb)) {
          scale.worst_bright_relative_mdb = kNaN;
        } else {
          scale.worst_bright_relative_mdb = std::max(scale.worst_bright_relative_mdb, relative);
        }
      }
      p_values.push_back(t.p_value);
      weights.push_back(1.0 / (levels * tests));
      scale.tests.push_back(t);
    }
    scale.median_bright_relative_mdb =
        relatives.empty() ? 0.0 : median_or_nan(std::move(relatives));
    out.scales.push_back(std::move(scale));
  }

  const std::vector<double> adjusted = weighted_holm_adjusted(p_values, weights);
  std::size_t next = 0;
  for (ScaleTests& scale : out.scales) {
    for (BlockTest& t : scale.tests) {
      t.p_adjusted = adjusted[next++];
      scale.min_p_adjusted = std::min(scale.min_p_adjusted, t.p_adjusted);
    }
    out.min_p_adjusted = std::min(out.min_p_adjusted, scale.min_p_adjusted);
  }
  out.tests = static_cast<std::uint32_t>(p_values.size());
  out.rejected = out.min_p_adjusted <= alpha;
  return out;
}

// One-sample tests of a's replicate block means against a reference's block means, whose
// variance is `reference_variance[s]` per block and channel at scale s (empty: exact).
PyramidResult blocks_against(std::span<const Image> a, const Image& reference,
                             const std::vector<std::vector<double>>& reference_variance,
                             const std::vector<Blocking>& scales, double alpha,
                             const PyramidOptions& options) {
  const std::vector<std::vector<double>> means_a = block_means(a, scales);
  const std::vector<std::vector<double>> means_reference =
      block_means(std::span(&reference, 1), scales);
  const double count = static_cast<double>(a.size());
  std::vector<std::vector<TwoSampleTest>> raw(scales.size());
  for (std::size_t s = 0; s < scales.size(); ++s) {
    raw[s].resize(scales[s].count() * kImageChannels);
    for (std::size_t k = 0; k < raw[s].size(); ++k) {
      Tally tally(0);
      for (std::size_t r = 0; r < a.size(); ++r) tally.add(means_a[s][k * a.size() + r], r);
      const double variance = reference_variance.empty() ? 0.0 : reference_variance[s][k];
      raw[s][k] = welch_test(tally.mean(), tally.variance() / count, count - 1.0,
                             means_reference[s][k], variance, kInf);
      // Welch's test with an exactly known b (variance 0, infinite dof) is Student's one-sample
      // test; its dof is R - 1 also where a does not vary (Welch would add b's infinity).
      if (variance == 0.0) raw[s][k].dof = count - 1.0;
    }
  }
  return decide_pyramid(raw, scales, alpha, options);
}

}  // namespace

std::vector<std::uint32_t> pyramid_block_sizes(std::uint32_t width, std::uint32_t height,
                                               std::uint32_t tile, std::uint32_t max_scales) {
  std::vector<std::uint32_t> sizes;
  if (tile == 0) return sizes;
  const std::uint64_t image = std::max(width, height);
  for (std::uint64_t block = tile;; block *= 2) {
    sizes.push_back(static_cast<std::uint32_t>(block));
    if (block >= image || (max_scales != 0 && sizes.size() == max_scales)) break;
  }
  return sizes;
}

PyramidResult compare_blocks(std::span<const Image> a, std::span<const Image> b, double alpha,
                             const PyramidOptions& options) {
  check_options(alpha, options);
  check_replicates(a);
  check_replicates(b, &a.front());
  if (a.front().pixel_count() == 0) throw std::invalid_argument("empty image");
  if (options.paired && a.size() != b.size()) {
    throw std::invalid_argument(fmt::format(
        "a paired comparison needs replicate pairs: {} replicates against {}", a.size(), b.size()));
  }
  const auto test = options.paired ? paired_t_test : welch_two_sample;
  const std::vector<Blocking> scales = pyramid(a.front(), options);
  const std::vector<std::vector<double>> means_a = block_means(a, scales);
  const std::vector<std::vector<double>> means_b = block_means(b, scales);
  std::vector<std::vector<TwoSampleTest>> raw(scales.size());
  for (std::size_t s = 0; s < scales.size(); ++s) {
    raw[s].resize(scales[s].count() * kImageChannels);
    for (std::size_t k = 0; k < raw[s].size(); ++k) {
      raw[s][k] = test(std::span(means_a[s]).subspan(k * a.size(), a.size()),
                       std::span(means_b[s]).subspan(k * b.size(), b.size()));
    }
  }
  PyramidResult out = decide_pyramid(raw, scales, alpha, options);
  out.paired = options.paired;
  return out;
}

PyramidResult test_blocks_against_exact(std::span<const Image> a, const Image& exact, double alpha,
                                        const PyramidOptions& options) {
  check_options(alpha, options);
  check_replicates(a);
  check_image(exact, a.front());
  if (exact.pixel_count() == 0) throw std::invalid_argument("empty image");
  return blocks_against(a, exact, {}, pyramid(exact, options), alpha, options);
}

PyramidResult test_blocks_against_reference(std::span<const Image> a, const Image& reference,
                                            const Image& reference_stderr, double alpha,
                                            const PyramidOptions& options) {
  check_options(alpha, options);
  check_replicates(a);
  check_image(reference, a.front());
  check_image(reference_stderr, a.front());
  if (reference.pixel_count() == 0) throw std::invalid_argument("empty image");
  const std::vector<Blocking> scales = pyramid(reference, options);
  // A block mean's variance: the sum of its pixels' variances over the pixel count squared.
  Image squared = reference_stderr;
  for (double& v : squared.values) v *= v;
  std::vector<std::vector<double>> variance = block_means(std::span(&squared, 1), scales);
  for (std::size_t s = 0; s < scales.size(); ++s) {
    for (std::size_t k = 0; k < variance[s].size(); ++k) {
      variance[s][k] /= scales[s].pixels(k / kImageChannels);
    }
  }
  return blocks_against(a, reference, variance, scales, alpha, options);
}

}  // namespace pcbench
