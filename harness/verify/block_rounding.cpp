#include "harness/verify/block_rounding.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcbench {
namespace {

// The mean over the block's pixels of one side's rounding bound in `channel`.
double block_bound(const SideRounding& side, std::uint32_t block, std::uint32_t bx,
                   std::uint32_t by, std::uint32_t channel) {
  if (side.mean == nullptr || side.relative == 0.0) return 0.0;
  const Image& image = *side.mean;
  const std::uint32_t x_end = std::min(image.width, (bx + 1) * block);
  const std::uint32_t y_end = std::min(image.height, (by + 1) * block);
  double sum = 0.0, pixels = 0.0;
  for (std::uint32_t y = by * block; y < y_end; ++y) {
    for (std::uint32_t x = bx * block; x < x_end; ++x) {
      double magnitude = std::fabs(image.at(x, y, channel));
      if (side.of_largest_channel) {
        for (std::uint32_t c = 0; c < kImageChannels; ++c) {
          magnitude = std::max(magnitude, std::fabs(image.at(x, y, c)));
        }
      }
      sum += magnitude;
      pixels += 1.0;
    }
  }
  return pixels > 0.0 ? side.relative * sum / pixels : 0.0;
}

}  // namespace

double worst_difference_over_rounding(const Comparison& c, const PyramidResult& t,
                                      std::span<const SideRounding> sides) {
  double worst = 0.0;
  for (const Comparison::BlockP& b : blocks_differing(c)) {
    const ScaleTests& scale = t.scales.at(b.scale);
    const BlockTest& test =
        scale.tests.at((std::size_t{b.y} * scale.columns + b.x) * kImageChannels + b.channel);
    double bound = 0.0;
    for (const SideRounding& side : sides)
      bound += block_bound(side, scale.block, b.x, b.y, b.channel);
    const double difference = std::fabs(test.mean_a - test.mean_b);
    const double ratio = bound > 0.0        ? difference / bound
                         : difference > 0.0 ? std::numeric_limits<double>::infinity()
                                            : 0.0;
    worst = std::isnan(ratio) ? ratio : std::max(worst, ratio);
  }
  return worst;
}

}  // namespace pcbench
