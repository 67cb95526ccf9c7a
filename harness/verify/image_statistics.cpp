#include "harness/verify/image_statistics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "base/tally.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// (mean_a - mean_b) / sqrt(variance), without the NaN of 0/0: two values known exactly are
// either equal (z = 0) or certainly different (±inf).
double z_score(double mean_a, double mean_b, double variance) {
  const double difference = mean_a - mean_b;
  if (variance == 0.0) return difference == 0.0 ? 0.0 : std::copysign(kInf, difference);
  return difference / std::sqrt(variance);
}

}  // namespace

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

void check_replicates(std::span<const Image> images, const Image* like) {
  if (images.size() < 2) {
    throw std::invalid_argument(
        fmt::format("{} replicate image(s): a standard error needs at least 2", images.size()));
  }
  for (const Image& image : images) check_image(image, like != nullptr ? *like : images.front());
}

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
