#include "harness/verify/pyramid_calibration.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

#include "harness/verify/block_checks.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kConfidence = 0.95;  // of the Wilson intervals

// A count over `trials` as a rate with its Wilson interval.
void rate(std::uint64_t count, std::uint32_t trials, double& value, double& low, double& high) {
  value = trials > 0 ? static_cast<double>(count) / trials : kNaN;
  const ProportionInterval ci = wilson_interval(count, trials, kConfidence);
  low = ci.low;
  high = ci.high;
}

// Scale s of a row, from the seeds' outcomes.
ScaleSizeRow scale_size_row(std::span<const SizeSeed> seeds, std::size_t s, double alpha,
                            double pass_threshold) {
  ScaleSizeRow row;
  const ScaleSeed& first = seeds.front().scales.at(s);
  row.block = first.block;
  row.tests = first.tests;
  row.centre_x = first.centre.x;
  row.centre_y = first.centre.y;
  row.centre_channel = first.centre.channel;
  std::vector<double> bright;
  for (const SizeSeed& seed : seeds) {
    const ScaleSeed& scale = seed.scales.at(s);
    row.min_p_adjusted.push_back(scale.min_p_adjusted);
    row.centre_p_values.push_back(scale.centre.p_value);
    bright.push_back(scale.bright_relative_mdb);
  }
  static_cast<FalseAlarms&>(row) = count_false_alarms(row.min_p_adjusted, alpha);
  const double levels = static_cast<double>(seeds.front().scales.size());
  row.expected_share = alpha / levels;
  row.expected_false_alarms = static_cast<double>(row.seeds) * row.expected_share;
  row.centre_ks = ks_uniform(row.centre_p_values);
  row.median_bright_relative_mdb = median_or_nan(std::move(bright));
  row.pass =
      row.binomial_upper_p_value >= pass_threshold && row.centre_ks.p_value >= pass_threshold;
  return row;
}

// The chosen block's index in the scale's tests.
std::size_t injected_index(const ScaleTests& scale, InjectionRule rule, const Image& like) {
  const BlockTest& block = rule == InjectionRule::kBrightest
                               ? brightest_block(scale)
                               : centre_block(scale, like.width, like.height);
  return static_cast<std::size_t>(&block - scale.tests.data());
}

// The injected blocks of a curve, most seeds first.
std::vector<InjectedBlock> injected_blocks(std::span<const InjectionSeed> seeds) {
  std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, std::uint32_t> counts;
  for (const InjectionSeed& p : seeds) ++counts[{p.block.x, p.block.y, p.block.channel}];
  std::vector<InjectedBlock> out;
  for (const auto& [key, count] : counts) {
    out.push_back({std::get<0>(key), std::get<1>(key), std::get<2>(key), count});
  }
  std::stable_sort(out.begin(), out.end(), [](const InjectedBlock& x, const InjectedBlock& y) {
    return x.seeds > y.seeds;
  });
  return out;
}

// The point at multiplier j of a curve.
BlockPowerPoint power_point(std::span<const InjectionSeed> seeds, std::size_t j, double k) {
  BlockPowerPoint point{.multiplier = k};
  double predicted = 0.0;
  for (const InjectionSeed& p : seeds) {
    point.detections += p.detected.at(j) ? 1 : 0;
    point.block_detections += p.block_detected.at(j) ? 1 : 0;
    predicted += p.predicted.at(j);
  }
  const auto n = static_cast<std::uint32_t>(seeds.size());
  rate(point.detections, n, point.detection_rate, point.wilson_low, point.wilson_high);
  rate(point.block_detections, n, point.block_detection_rate, point.block_wilson_low,
       point.block_wilson_high);
  point.predicted_power = predicted / static_cast<double>(n);
  return point;
}

}  // namespace

const BlockTest& centre_block(const ScaleTests& scale, std::uint32_t width, std::uint32_t height) {
  const std::uint32_t bx = (width / 2) / scale.block, by = (height / 2) / scale.block;
  const auto it = std::find_if(scale.tests.begin(), scale.tests.end(), [&](const BlockTest& t) {
    return t.x == bx && t.y == by && t.channel == kCentreChannel;
  });
  if (it == scale.tests.end()) {
    throw std::logic_error(fmt::format("no centre block at scale {} px", scale.block));
  }
  return *it;
}

SizeSeed size_seed(const PyramidResult& t, std::uint32_t width, std::uint32_t height) {
  SizeSeed out{.min_p_adjusted = t.min_p_adjusted, .tests = t.tests};
  for (const ScaleTests& scale : t.scales) {
    out.scales.push_back({.block = scale.block,
                          .tests = static_cast<std::uint32_t>(scale.tests.size()),
                          .min_p_adjusted = scale.min_p_adjusted,
                          .bright_relative_mdb = scale.worst_bright_relative_mdb,
                          .centre = centre_block(scale, width, height)});
  }
  return out;
}

FalseAlarms count_false_alarms(std::span<const double> min_p_adjusted, double alpha) {
  FalseAlarms out;
  out.seeds = static_cast<std::uint32_t>(min_p_adjusted.size());
  out.false_alarms = static_cast<std::uint64_t>(std::count_if(
      min_p_adjusted.begin(), min_p_adjusted.end(), [&](double p) { return p <= alpha; }));
  rate(out.false_alarms, out.seeds, out.false_alarm_rate, out.wilson_low, out.wilson_high);
  out.binomial_p_value = binomial_test_p_value(out.false_alarms, out.seeds, alpha);
  out.binomial_upper_p_value = binomial_upper_p_value(out.false_alarms, out.seeds, alpha);
  return out;
}

PyramidSizeRow pyramid_size_row(std::span<const SizeSeed> seeds, double alpha,
                                double pass_threshold) {
  if (seeds.empty()) throw std::invalid_argument("pyramid_size_row: no seeds");
  PyramidSizeRow row;
  row.tests = seeds.front().tests;
  for (const SizeSeed& seed : seeds) {
    if (seed.scales.size() != seeds.front().scales.size()) {
      throw std::invalid_argument("pyramid_size_row: seeds with different scales");
    }
    row.min_p_adjusted.push_back(seed.min_p_adjusted);
  }
  static_cast<FalseAlarms&>(row) = count_false_alarms(row.min_p_adjusted, alpha);
  row.expected_false_alarms = static_cast<double>(row.seeds) * alpha;
  row.pass = row.binomial_upper_p_value >= pass_threshold;
  for (std::size_t s = 0; s < seeds.front().scales.size(); ++s) {
    row.scales.push_back(scale_size_row(seeds, s, alpha, pass_threshold));
    row.pass = row.pass && row.scales.back().pass;
  }
  return row;
}

const char* rule_name(InjectionRule rule) {
  return rule == InjectionRule::kBrightest ? "brightest" : "centre";
}

InjectionSeed inject_own_mdb(const PyramidResult& t, std::size_t scale, InjectionRule rule,
                             const std::vector<Image>& a, const Retest& retest,
                             std::span<const double> multipliers, double alpha) {
  const ScaleTests& tests = t.scales.at(scale);
  const std::size_t index = injected_index(tests, rule, a.front());
  InjectionSeed p{.block_size = tests.block,
                  .tests = static_cast<std::uint32_t>(tests.tests.size()),
                  .pyramid_tests = t.tests,
                  .share = tests.detection_share,
                  .block = tests.tests[index]};
  const BlockTest& block = p.block;
  p.mdb = block.min_detectable_bias;
  p.multiplier = detectable_multiplier(p.share, block.dof, PyramidOptions{}.power);
  p.stderr_of_difference = p.mdb / p.multiplier;
  // The MDB must be the one this decision implies, the statistic's own standard error times m;
  // otherwise the power below would be predicted for another threshold.
  if (block.statistic != 0.0 && std::isfinite(block.statistic) && std::isfinite(p.mdb)) {
    const double se = (block.mean_a - block.mean_b) / block.statistic;
    if (!(std::fabs(se - p.stderr_of_difference) <= 1e-9 * std::fabs(se))) {
      throw std::logic_error(fmt::format(
          "pyramid calibration: the reported MDB {} at {} px is not m(share {}) x stderr {}", p.mdb,
          tests.block, p.share, se));
    }
  }
  for (const double k : multipliers) {
    const PyramidResult shifted = retest(with_block_bias(a, block, tests.block, k * p.mdb));
    p.detected.push_back(shifted.min_p_adjusted <= alpha);
    p.block_detected.push_back(shifted.scales.at(scale).tests.at(index).p_value <= p.share);
    // A block known exactly detects any bias.
    p.predicted.push_back(p.mdb > 0.0 ? shifted_t_power(k * p.multiplier, block.dof, p.share)
                                      : 1.0);
  }
  return p;
}

ScalePowerCurve scale_power_curve(std::span<const InjectionSeed> seeds, InjectionRule rule,
                                  std::size_t scale, std::span<const double> multipliers) {
  if (seeds.empty()) throw std::invalid_argument("scale_power_curve: no seeds");
  const InjectionSeed& first = seeds.front();
  ScalePowerCurve curve{.block_rule = rule_name(rule),
                        .scale = static_cast<std::uint32_t>(scale),
                        .block = first.block_size,
                        .tests = first.tests,
                        .pyramid_tests = first.pyramid_tests,
                        .seeds = static_cast<std::uint32_t>(seeds.size()),
                        .share = first.share};
  std::vector<double> mdbs, dofs, relative;
  double se2 = 0.0, statistic = 0.0;
  for (const InjectionSeed& p : seeds) {
    mdbs.push_back(p.mdb);
    dofs.push_back(p.block.dof);
    const double block_mean = 0.5 * (p.block.mean_a + p.block.mean_b);
    if (block_mean > 0.0) relative.push_back(p.mdb / block_mean);
    se2 += p.stderr_of_difference * p.stderr_of_difference;
    statistic += p.block.statistic;
  }
  const double n = static_cast<double>(seeds.size());
  curve.median_mdb = median_or_nan(mdbs);
  curve.median_dof = median_or_nan(dofs);
  curve.median_relative_mdb = median_or_nan(relative);
  curve.rms_stderr = std::sqrt(se2 / n);
  curve.mean_statistic = statistic / n;
  curve.injected_blocks = injected_blocks(seeds);
  for (std::size_t j = 0; j < multipliers.size(); ++j) {
    curve.points.push_back(power_point(seeds, j, multipliers[j]));
  }
  return curve;
}

}  // namespace pcbench
