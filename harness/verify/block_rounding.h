// Whether the blocks that make an image comparison differ could differ by the files' rounding
// alone. Stored pixels round: half to within 2^-11 of the value, RGBE's shared exponent to within
// 2^-7 of the pixel's LARGEST channel (harness/plan/image_set.h, worst_quantisation_bias), so a
// minor channel of a saturated colour (a red wall's green) may move by several percent of
// itself. A block mean inherits at most the mean of its pixels' bounds; at the power a pyramid
// reaches (a whole image tested to 0.05%), that rounding is a real, detectable difference. The
// verdict stays biased, but a reader should be told that the format may be what differs.
#pragma once

#include <span>

#include "harness/verify/block_pyramid.h"
#include "harness/verify/report_compare.h"
#include "results/image.h"

namespace pcbench {

// One side's worst-case rounding: `relative` of each stored value, or of each pixel's largest
// channel (RGBE), applied to the side's mean image.
struct SideRounding {
  const Image* mean = nullptr;  // null: an exact side (a constant), no rounding
  double relative = 0.0;
  bool of_largest_channel = false;
};

// Over the blocks that differ in `c` (blocks_differing, after the family has decided), the
// largest |mean_a - mean_b| divided by the sum of both sides' rounding bounds of that block's
// mean (+inf where a bound is 0 and the means differ; 0 when no block differs). At most 1: every
// difference that decides the comparison is within the files' worst-case rounding. `t` is the
// pyramid `c` was made from.
double worst_difference_over_rounding(const Comparison& c, const PyramidResult& t,
                                      std::span<const SideRounding> sides);

}  // namespace pcbench
