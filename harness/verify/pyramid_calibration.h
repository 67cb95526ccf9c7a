// The statistics of the block pyramid's calibration (harness/verify/block_pyramid.h): what
// `pcbench calibrate` on scenes computes from the images it renders (the command,
// harness/commands/tile_calibration.h, plans, renders, prints and writes).
//
// Each comparison is decided alone (a family of one, family_size 1) at alpha = test_alpha over
// the whole pyramid: L scales, n_s block×channel tests at scale s, a weighted Holm with weight
// 1 / (L n_s), so the first step holds a test of scale s to its detection share
// alpha / (L n_s) and each scale to alpha / L.
//
//  1. Size, per seed: the comparison rejects (its smallest adjusted p <= alpha), and it rejects
//     through scale s (that scale's smallest adjusted p <= alpha). Over seeds each is a
//     false-alarm count, tested against Binomial(seeds, alpha) one-sided: Holm is conservative
//     and the channels of a block (and the blocks of nested scales) are correlated, so a correct
//     pyramid has a rate at most alpha overall, and at most about alpha / L per scale (its share
//     at Holm's first step; later steps may let a scale reject once another has). The smallest
//     adjusted p is not uniform, so it is not KS-tested; the raw p of one block fixed before the
//     sample is seen, the one holding the image centre in green, should be U(0, 1) across seeds
//     at every scale (Kolmogorov–Smirnov).
//  2. Power, per scale: a bias of k × the comparison's own reported MDB of one block of that
//     scale is added to every pixel of that block (its channel) in a's images and the whole
//     pyramid is tested again. The bias is then k × m × the block's own estimated standard error
//     (m = t_{1-s/2,ν} + t_{power,ν}, s the scale's detection share, ν the block test's dof), so
//     the block's statistic moves by exactly k·m (adding a constant leaves the spread alone) and
//     its raw p falls to s or below with probability shifted_t_power(k m, ν, s): the nominal
//     power at k = 1. The prediction is for the block's own test at its share, counted too; a
//     detection is the pyramid rejecting, which the other blocks' false alarms and the bias's
//     share of the blocks holding or held by this one can only make more likely. Two rules
//     choose the block: the brightest (brightest_block, the session's self-check rule, chosen
//     on the sample tested: its unbiased statistic need not be centred, mean_statistic) and the
//     block holding the image centre in green (chosen before any sample is seen: the
//     prediction's own promise).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "harness/run/diagnostics.h"
#include "harness/verify/block_pyramid.h"
#include "results/image.h"

namespace pcbench {

// The channel of the fixed (centre) blocks: green, lit at the centre of every built-in scene.
inline constexpr std::uint32_t kCentreChannel = 1;

// The test of `scale` whose block holds the image centre (width / 2, height / 2), in
// kCentreChannel. Throws std::logic_error if the scale has no such test.
const BlockTest& centre_block(const ScaleTests& scale, std::uint32_t width, std::uint32_t height);

// What the size rows need of one seed's comparison at one scale.
struct ScaleSeed {
  std::uint32_t block = 0;  // edge in pixels
  std::uint32_t tests = 0;  // n_s
  double min_p_adjusted = 1.0;
  double bright_relative_mdb = 0.0;  // the scale's worst_bright_relative_mdb
  BlockTest centre = {};             // the centre block's test
};

// ... and of the whole comparison.
struct SizeSeed {
  double min_p_adjusted = 1.0;
  std::uint32_t tests = 0;  // over every scale
  std::vector<ScaleSeed> scales = {};
};

SizeSeed size_seed(const PyramidResult& t, std::uint32_t width, std::uint32_t height);

// A false-alarm count over seeds, with its 95% Wilson interval and its binomial tests against
// alpha.
struct FalseAlarms {
  std::uint32_t seeds = 0;
  std::uint64_t false_alarms = 0;  // seeds with a p <= alpha
  double false_alarm_rate = 0.0;
  double wilson_low = 0.0, wilson_high = 1.0;
  double binomial_p_value = 1.0;        // two-sided, against Binomial(seeds, alpha)
  double binomial_upper_p_value = 1.0;  // P(X >= false_alarms): the pass criterion
};

FalseAlarms count_false_alarms(std::span<const double> min_p_adjusted, double alpha);

// One scale of a size row: the comparison rejecting through this scale.
struct ScaleSizeRow : FalseAlarms {
  std::uint32_t block = 0;
  std::uint32_t tests = 0;                  // n_s
  double expected_share = 0.0;              // alpha / L: the scale's part of the budget
  double expected_false_alarms = 0.0;       // seeds × alpha / L
  std::vector<double> min_p_adjusted = {};  // per seed, the scale's smallest adjusted p
  std::uint32_t centre_x = 0, centre_y = 0, centre_channel = kCentreChannel;
  std::vector<double> centre_p_values = {};  // per seed, the centre block's raw p
  KsResult centre_ks = {};
  double median_bright_relative_mdb = 0.0;  // over seeds (NaN if one is)
  bool pass = false;  // binomial_upper_p_value and centre_ks.p_value >= the pass threshold
};

// The size of one comparison over seeds: overall and per scale.
struct PyramidSizeRow : FalseAlarms {
  std::uint32_t tests = 0;                  // over every scale
  double expected_false_alarms = 0.0;       // seeds × alpha: what Holm allows at most
  std::vector<double> min_p_adjusted = {};  // per seed, the comparison's p
  std::vector<ScaleSizeRow> scales = {};    // the tiles first
  bool pass = false;  // its binomial_upper_p_value >= the threshold and every scale passes
};

// The row from the seeds' outcomes (in seed order; every seed of one comparison has the same
// scales). Throws std::invalid_argument without seeds.
PyramidSizeRow pyramid_size_row(std::span<const SizeSeed> seeds, double alpha,
                                double pass_threshold);

// Which block of a scale a power curve's bias goes into, per seed.
enum class InjectionRule {
  kBrightest,  // brightest_block: the session's self-check, chosen on the same sample
  kCentre,     // centre_block: chosen before any sample is seen
};
const char* rule_name(InjectionRule rule);  // "brightest", "centre"

// The pyramid of the biased images (a's with the bias added; b or the exact image unchanged).
using Retest = std::function<PyramidResult(const std::vector<Image>&)>;

// One seed's injections at one scale, for every k.
struct InjectionSeed {
  std::uint32_t block_size = 0;                // the scale's edge in pixels
  std::uint32_t tests = 0, pyramid_tests = 0;  // n_s, and over every scale
  double share = 0.0;                          // the scale's detection share
  BlockTest block = {};                        // the injected block's test before the bias
  double mdb = 0.0;                            // its reported MDB
  double multiplier = 0.0;                     // m at the scale's share and the block's dof
  double stderr_of_difference = 0.0;           // mdb / m
  std::vector<bool> detected = {};             // per k: the pyramid rejects
  std::vector<bool> block_detected = {};       // per k: the block's own raw p <= its share
  std::vector<double> predicted = {};          // per k: shifted_t_power(k m, dof, share)
};

// k × the reported MDB of the block chosen by `rule` at scale `scale` of t (the comparison of
// `a` decided alone at alpha) into `a`, each retested. Throws std::logic_error when the MDB is
// not m × the statistic's own standard error (the prediction would be for another threshold).
InjectionSeed inject_own_mdb(const PyramidResult& t, std::size_t scale, InjectionRule rule,
                             const std::vector<Image>& a, const Retest& retest,
                             std::span<const double> multipliers, double alpha);

// The detections at one k over seeds.
struct BlockPowerPoint {
  double multiplier = 0.0;             // k
  std::uint32_t detections = 0;        // the pyramid rejected
  std::uint32_t block_detections = 0;  // the injected block's own raw p <= the share
  double detection_rate = 0.0;
  double wilson_low = 0.0, wilson_high = 1.0;  // 95%
  double block_detection_rate = 0.0;
  double block_wilson_low = 0.0, block_wilson_high = 1.0;
  double predicted_power = 0.0;  // mean over seeds of shifted_t_power(k m, ν, share)
};

// Which block×channel took the bias, and in how many seeds.
struct InjectedBlock {
  std::uint32_t x = 0, y = 0, channel = 0;
  std::uint32_t seeds = 0;
};

// A power curve at one scale, by one rule, over seeds.
struct ScalePowerCurve {
  std::string block_rule = {};  // rule_name
  std::uint32_t scale = 0;      // 0: the tiles
  std::uint32_t block = 0;      // edge in pixels
  std::uint32_t tests = 0;      // n_s
  std::uint32_t pyramid_tests = 0;
  std::uint32_t seeds = 0;
  double share = 0.0;                // the scale's detection share, alpha / (L n_s)
  double median_mdb = 0.0;           // of the injected block
  double median_relative_mdb = 0.0;  // of MDB / the injected block's mean
  double rms_stderr = 0.0;           // of the injected block's difference: sqrt of the mean of se²
  double median_dof = 0.0;
  // Mean of the injected block's statistic before the bias: 0 in expectation for a block chosen
  // without looking at the sample (see the header).
  double mean_statistic = 0.0;
  std::vector<InjectedBlock> injected_blocks = {};  // most seeds first
  std::vector<BlockPowerPoint> points = {};
};

// The curve from its seeds' injections (in seed order, each with one entry per multiplier).
// Throws std::invalid_argument without seeds.
ScalePowerCurve scale_power_curve(std::span<const InjectionSeed> seeds, InjectionRule rule,
                                  std::size_t scale, std::span<const double> multipliers);

}  // namespace pcbench
