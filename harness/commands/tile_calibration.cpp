#include "harness/commands/tile_calibration.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <ostream>

#include "base/json_number.h"
#include "harness/commands/calibration.h"
#include "harness/verify/block_pyramid.h"

namespace pcbench {
namespace {

using Json = nlohmann::ordered_json;

Json numbers(const std::vector<double>& values) {
  Json out = Json::array();
  for (double v : values) out.push_back(finite_or_null(v));
  return out;
}

void add_false_alarms(Json& j, const FalseAlarms& f) {
  j["seeds"] = f.seeds;
  j["false_alarms"] = f.false_alarms;
  j["false_alarm_rate"] = finite_or_null(f.false_alarm_rate);
  j["wilson_low"] = finite_or_null(f.wilson_low);
  j["wilson_high"] = finite_or_null(f.wilson_high);
  j["binomial_p_value"] = finite_or_null(f.binomial_p_value);
  j["binomial_upper_p_value"] = finite_or_null(f.binomial_upper_p_value);
}

Json scale_row_json(const ScaleSizeRow& s) {
  Json j = Json::object();
  j["block"] = s.block;
  j["tests"] = s.tests;
  add_false_alarms(j, s);
  j["expected_share"] = finite_or_null(s.expected_share);
  j["expected_false_alarms"] = finite_or_null(s.expected_false_alarms);
  j["centre_block"] = {{"x", s.centre_x},
                       {"y", s.centre_y},
                       {"channel", s.centre_channel},
                       {"ks_statistic", finite_or_null(s.centre_ks.statistic)},
                       {"ks_p_value", finite_or_null(s.centre_ks.p_value)},
                       {"p_values", numbers(s.centre_p_values)}};
  j["median_bright_relative_mdb"] = finite_or_null(s.median_bright_relative_mdb);
  j["pass"] = s.pass;
  j["min_p_adjusted"] = numbers(s.min_p_adjusted);
  return j;
}

Json row_json(const TileSizeRow& row) {
  Json j = Json::object();
  j["scene"] = row.scene;
  j["width"] = row.width;
  j["height"] = row.height;
  j["estimator_a"] = row.estimator_a;
  j["estimator_b"] = row.estimator_b;
  j["run_a"] = row.run_a;
  j["run_b"] = row.run_b;
  j["biased"] = row.biased;
  j["tests"] = row.tests;
  add_false_alarms(j, row);
  j["expected_false_alarms"] = finite_or_null(row.expected_false_alarms);
  j["pass"] = row.pass;
  Json scales = Json::array();
  for (const ScaleSizeRow& s : row.scales) scales.push_back(scale_row_json(s));
  j["scales"] = std::move(scales);
  j["min_p_adjusted"] = numbers(row.min_p_adjusted);
  return j;
}

Json point_json(const BlockPowerPoint& p) {
  return Json{{"multiplier", finite_or_null(p.multiplier)},
              {"detections", p.detections},
              {"detection_rate", finite_or_null(p.detection_rate)},
              {"wilson_low", finite_or_null(p.wilson_low)},
              {"wilson_high", finite_or_null(p.wilson_high)},
              {"block_detections", p.block_detections},
              {"block_detection_rate", finite_or_null(p.block_detection_rate)},
              {"block_wilson_low", finite_or_null(p.block_wilson_low)},
              {"block_wilson_high", finite_or_null(p.block_wilson_high)},
              {"predicted_power", finite_or_null(p.predicted_power)}};
}

Json curve_json(const TilePowerCurve& c) {
  Json blocks = Json::array();
  for (const InjectedBlock& b : c.injected_blocks) {
    blocks.push_back(Json{{"x", b.x}, {"y", b.y}, {"channel", b.channel}, {"seeds", b.seeds}});
  }
  Json points = Json::array();
  for (const BlockPowerPoint& p : c.points) points.push_back(point_json(p));
  return Json{{"scene", c.scene},
              {"width", c.width},
              {"height", c.height},
              {"estimator_a", c.estimator_a},
              {"estimator_b", c.estimator_b},
              {"run_a", c.run_a},
              {"run_b", c.run_b},
              {"block_rule", c.block_rule},
              {"scale", c.scale},
              {"block", c.block},
              {"tests", c.tests},
              {"pyramid_tests", c.pyramid_tests},
              {"seeds", c.seeds},
              {"share", finite_or_null(c.share)},
              {"median_mdb", finite_or_null(c.median_mdb)},
              {"median_relative_mdb", finite_or_null(c.median_relative_mdb)},
              {"rms_stderr", finite_or_null(c.rms_stderr)},
              {"median_dof", finite_or_null(c.median_dof)},
              {"mean_statistic", finite_or_null(c.mean_statistic)},
              {"injected_blocks", std::move(blocks)},
              {"points", std::move(points)}};
}

std::string interval(double rate, double low, double high) {
  return fmt::format("{:.3f} [{:.3f}, {:.3f}]", rate, low, high);
}

std::string scale_name(std::uint32_t block, bool whole) {
  return whole ? fmt::format("{} px (whole image)", block) : fmt::format("{} px", block);
}

void print_size_table(const TileCalibrationResult& result, std::ostream& out) {
  const TileCalibrationOptions& o = result.options;
  out << fmt::format(
      "Block pyramid calibration: seeds {}..{}, {} replicate images x {} spp{}; each comparison "
      "decided alone at alpha = {} over its pyramid (weighted Holm: each of L scales alpha / L, "
      "each of its n_s block tests alpha / (L n_s)); a scale's false alarm is the comparison "
      "rejecting through that scale; a row passes when its one-sided binomial p against alpha, "
      "and at every scale that p and its centre block's KS p, are >= {}\n",
      o.first_seed, o.first_seed + o.seeds - 1, o.replicates, o.samples,
      o.paired ? ", paired streams (pairs tested on replicate differences)" : "", o.test_alpha,
      o.pass_threshold);
  out << fmt::format("{:<14} {:<44} {:>5} {:>12} {:>22} {:>8} {:>9} {:>9} {:>9}  {}\n", "scene",
                     "comparison / scale (its share alpha / L)", "tests", "false alarms",
                     "rate [95% Wilson]", "expected", "binom p", "upper p", "centre KS", "pass");
  const auto line = [&](const std::string& scene, const std::string& name, std::uint32_t tests,
                        const FalseAlarms& f, double expected, const std::string& ks, bool pass) {
    out << fmt::format("{:<14} {:<44} {:>5} {:>12} {:>22} {:>8.1f} {:>9.3g} {:>9.3g} {:>9}  {}\n",
                       scene, name, tests, fmt::format("{} / {}", f.false_alarms, f.seeds),
                       interval(f.false_alarm_rate, f.wilson_low, f.wilson_high), expected,
                       f.binomial_p_value, f.binomial_upper_p_value, ks, pass ? "yes" : "NO");
  };
  for (const TileSizeRow& row : result.rows) {
    line(fmt::format("{} {}x{}", row.scene, row.width, row.height),
         fmt::format("{} vs {}{}", row.estimator_a, row.estimator_b, row.biased ? " (biased)" : ""),
         row.tests, row, row.expected_false_alarms, "", row.pass);
    for (std::size_t s = 0; s < row.scales.size(); ++s) {
      const ScaleSizeRow& scale = row.scales[s];
      line("",
           fmt::format("  {}, share {:.3g}", scale_name(scale.block, s + 1 == row.scales.size()),
                       scale.expected_share),
           scale.tests, scale, scale.expected_false_alarms,
           fmt::format("{:.3g}", scale.centre_ks.p_value), scale.pass);
    }
  }
  out << fmt::format("pyramid calibration: {}\n", result.pass ? "pass" : "FAIL");
}

// One curve: its scale's line, then a line per k.
void print_curve(const TilePowerCurve& c, bool whole, std::ostream& out) {
  const InjectedBlock& top = c.injected_blocks.front();
  out << fmt::format(
      "  {}: {} tests, share {:.3g}; block {},{} channel {} in {} of {} seeds; median dof "
      "{:.1f}, median MDB {:.4g} ({:.3g}% of the block mean), RMS stderr {:.4g}, mean statistic "
      "before the bias {:.3f}\n",
      scale_name(c.block, whole), c.tests, c.share, top.x, top.y, top.channel, top.seeds, c.seeds,
      c.median_dof, c.median_mdb, 100.0 * c.median_relative_mdb, c.rms_stderr, c.mean_statistic);
  for (const BlockPowerPoint& p : c.points) {
    out << fmt::format(
        "    k = {:<4} detected {:>9} {:>22}   block alone {:>22}   predicted {:.3f}\n",
        p.multiplier, fmt::format("{}/{}", p.detections, c.seeds),
        interval(p.detection_rate, p.wilson_low, p.wilson_high),
        interval(p.block_detection_rate, p.block_wilson_low, p.block_wilson_high),
        p.predicted_power);
  }
}

}  // namespace

nlohmann::ordered_json tile_calibration_json(const TileCalibrationResult& result) {
  const TileCalibrationOptions& o = result.options;
  Json params = Json::object();
  for (const auto& [key, value] : o.params) params[key] = value;
  Json rows = Json::array();
  for (const TileSizeRow& row : result.rows) rows.push_back(row_json(row));
  Json curves = Json::array();
  for (const TilePowerCurve& c : result.power) curves.push_back(curve_json(c));
  Json j = Json::object();
  j["estimators"] = o.estimators;
  j["scenes"] = o.scenes;
  j["params"] = std::move(params);
  j["samples"] = o.samples;
  j["replicates"] = o.replicates;
  j["seeds"] = o.seeds;
  j["first_seed"] = o.first_seed;
  j["test_alpha"] = o.test_alpha;
  j["paired"] = o.paired;
  j["tile"] = PyramidOptions{}.tile;
  j["power"] = PyramidOptions{}.power;
  j["bias_multipliers"] = o.bias_multipliers;
  j["pass_threshold"] = o.pass_threshold;
  j["pass"] = result.pass;
  j["rows"] = std::move(rows);
  j["power_curves"] = std::move(curves);
  j["wall_seconds"] = finite_or_null(result.wall_seconds);
  return j;
}

void print_tile_calibration(const TileCalibrationResult& result, std::ostream& out) {
  print_size_table(result, out);
  for (std::size_t c = 0; c < result.power.size(); ++c) {
    const TilePowerCurve& curve = result.power[c];
    const bool first = c == 0 || result.power[c - 1].block_rule != curve.block_rule ||
                       result.power[c - 1].run_a != curve.run_a;
    if (first) {
      out << fmt::format(
          "\nPower on {} ({}x{}): a bias of k x the comparison's own MDB of the {} at each scale "
          "in {}'s images, against {}; the pyramid of {} tests decided alone at alpha = {}; "
          "detected: the pyramid rejects; block alone: its own raw p <= its share; predicted: "
          "shifted t\n",
          curve.scene, curve.width, curve.height,
          curve.block_rule == "brightest" ? "brightest block (the self-check's rule)"
                                          : "centre block, green (fixed)",
          curve.estimator_a, curve.estimator_b, curve.pyramid_tests, result.options.test_alpha);
    }
    const bool whole = c + 1 == result.power.size() || result.power[c + 1].scale == 0;
    print_curve(curve, whole, out);
  }
}

int run_tile_calibration(const TileCalibrationOptions& options, const SessionOptions& session,
                         std::ostream& out, std::ostream& err) {
  return run_self_test(
      "tile calibration", options.first_seed, session, out, err,
      [&] { return calibrate_tiles(options); }, print_tile_calibration,
      [](const TileCalibrationResult& result, ReportSections& sections) {
        sections.tile_calibration = nlohmann::json(tile_calibration_json(result));
      });
}

}  // namespace pcbench
