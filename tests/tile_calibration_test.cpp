#include "harness/commands/tile_calibration.h"

#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "base/errors.h"
#include "harness/commands/calibration.h"
#include "harness/verify/block_checks.h"
#include "harness/verify/pyramid_calibration.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

// The short form (CI): 16×16 images of the furnace against its exact image and of cornell
// between pt and plain, 8 replicates × 2 spp, 100 seeds. Their pyramids have 2 scales: 4 tiles
// × 3 channels = 12 tests, and the whole image's 3.
TileCalibrationOptions short_options() {
  TileCalibrationOptions options;
  options.params = {{"resolution", "16"}};
  options.samples = 2;
  options.replicates = 8;
  options.seeds = 100;
  options.first_seed = 1;
  return options;
}

const BlockPowerPoint& point_at(const TilePowerCurve& curve, double k) {
  for (const BlockPowerPoint& p : curve.points) {
    if (p.multiplier == k) return p;
  }
  throw std::logic_error("no point at that k");
}

// The size rows' structure: per scale, the counts of its tests and seeds, and the comparison
// rejecting exactly when some scale does.
void expect_scale_rows(const TileSizeRow& row, const std::vector<std::uint32_t>& blocks,
                       std::uint32_t seeds, double alpha) {
  const std::string name = row.scene + " " + row.estimator_a + " vs " + row.estimator_b;
  ASSERT_EQ(row.scales.size(), blocks.size()) << name;
  std::uint32_t tests = 0;
  for (std::size_t s = 0; s < blocks.size(); ++s) {
    const ScaleSizeRow& scale = row.scales[s];
    const std::uint32_t per_side = (row.width + blocks[s] - 1) / blocks[s];
    EXPECT_EQ(scale.block, blocks[s]) << name;
    EXPECT_EQ(scale.tests, per_side * per_side * 3) << name << " " << blocks[s] << " px";
    EXPECT_EQ(scale.seeds, seeds) << name;
    EXPECT_EQ(scale.min_p_adjusted.size(), seeds) << name;
    EXPECT_EQ(scale.centre_p_values.size(), seeds) << name;
    EXPECT_DOUBLE_EQ(scale.expected_share, alpha / static_cast<double>(blocks.size()));
    EXPECT_LE(scale.false_alarms, row.false_alarms) << name;
    tests += scale.tests;
  }
  EXPECT_EQ(row.tests, tests) << name;
  ASSERT_EQ(row.min_p_adjusted.size(), seeds) << name;
  for (std::size_t i = 0; i < seeds; ++i) {
    double smallest = 1.0;
    for (const ScaleSizeRow& scale : row.scales) {
      smallest = std::min(smallest, scale.min_p_adjusted[i]);
    }
    EXPECT_EQ(row.min_p_adjusted[i], smallest) << name << ", seed " << i;
  }
}

// Checks of a calibration of honest estimators whose pyramids have the scales `blocks`; shared
// by the CI and the full test. Error budget at a random seed (the seeds are fixed, so the tests
// are deterministic):
//  - every size row passes at the calibration's own threshold 1e-3: its binomial test, and per
//    scale its binomial test (rate about alpha / L against alpha: all but never fails) and its
//    centre block's KS test;
//  - the centre block (chosen before the sample is seen), per scale and k: the prediction of the
//    injected block's own test inside the 99.9% Wilson interval of its measured rate (1e-3);
//  - the brightest block (the self-check's rule, chosen on the sample tested): the measured rate
//    not below the prediction (its 99.9% Wilson upper end >= the prediction: 1e-3 each). It may
//    be above it: the largest block mean of a can favour blocks whose noise in a is positive, so
//    the unbiased statistic there need not be centred (mean_statistic);
//  - at k = 2 both rules detect in at least 90% of the seeds at every scale, the pyramid and the
//    block alone (predicted > 0.99: with 100 seeds, 10 misses or more have probability < 1e-4);
//  - a detection is the pyramid's, so never rarer than the block's own.
// With 3 rows × (1 + L) KS and binomial tests, and 2 L curves × 3 points, at 1e-3, and 2 L at
// 1e-4, a correct pyramid fails here with probability <= 2.7% for L = 2 (3.8% for L = 3).
void expect_calibrated(const TileCalibrationResult& result,
                       const std::vector<std::uint32_t>& blocks) {
  const std::uint32_t seeds = result.options.seeds;
  for (const TileSizeRow& row : result.rows) {
    const std::string name = row.scene + " " + row.estimator_a + " vs " + row.estimator_b;
    EXPECT_FALSE(row.biased) << name;
    EXPECT_GE(row.binomial_upper_p_value, 1e-3) << name << ": " << row.false_alarms << " alarms";
    for (const ScaleSizeRow& scale : row.scales) {
      EXPECT_GE(scale.binomial_upper_p_value, 1e-3) << name << " " << scale.block << " px";
      EXPECT_GE(scale.centre_ks.p_value, 1e-3) << name << " " << scale.block << " px";
      EXPECT_TRUE(scale.pass) << name << " " << scale.block << " px";
    }
    EXPECT_TRUE(row.pass) << name;
    EXPECT_EQ(row.seeds, seeds);
    expect_scale_rows(row, blocks, seeds, result.options.test_alpha);
  }
  EXPECT_TRUE(result.pass);
  ASSERT_EQ(result.power.size(), 2 * blocks.size());
  for (std::size_t c = 0; c < result.power.size(); ++c) {
    const TilePowerCurve& curve = result.power[c];
    const bool centre = c >= blocks.size();
    EXPECT_EQ(curve.block_rule, centre ? "centre" : "brightest");
    EXPECT_EQ(curve.block, blocks[c % blocks.size()]);
    ASSERT_EQ(curve.points.size(), 3u);
    const std::string rule = curve.block_rule + " at " + std::to_string(curve.block) + " px";
    for (const BlockPowerPoint& p : curve.points) {
      const std::string where = rule + ", k = " + std::to_string(p.multiplier);
      const ProportionInterval own = wilson_interval(p.block_detections, curve.seeds, 0.999);
      EXPECT_LE(p.predicted_power, own.high) << where;
      if (centre) {
        EXPECT_GE(p.predicted_power, own.low) << where;
      }
      EXPECT_GE(p.detections, p.block_detections) << where;
    }
    // At k = 1 the MDB's promise: the nominal power 0.8, predicted up to the far tail.
    EXPECT_NEAR(point_at(curve, 1.0).predicted_power, 0.8, 1e-4) << rule;
    EXPECT_GE(point_at(curve, 2.0).block_detection_rate, 0.9) << rule;
    EXPECT_GE(point_at(curve, 2.0).detection_rate, 0.9) << rule;
    EXPECT_GT(point_at(curve, 2.0).predicted_power, 0.99) << rule;
    EXPECT_LT(point_at(curve, 0.5).predicted_power, 0.5) << rule;
    if (centre) {
      EXPECT_EQ(curve.injected_blocks.size(), 1u) << rule;
    }
  }
}

TEST(TileCalibration, ShortFormIsCalibrated) {
  const TileCalibrationResult result = calibrate_tiles(short_options());
  print_tile_calibration(result, std::cout);
  std::cout << "calibrate_tiles() took " << result.wall_seconds << " s\n";
  ASSERT_EQ(result.rows.size(), 3u);  // furnace: pt, plain against exact; cornell: pt vs plain
  EXPECT_EQ(result.rows[0].estimator_b, "exact");
  EXPECT_EQ(result.rows[1].estimator_b, "exact");
  EXPECT_EQ(result.rows[2].scene, "cornell");
  EXPECT_EQ(result.rows[2].tests, 15u);
  EXPECT_NE(result.rows[2].run_a, result.rows[2].run_b);  // independent streams
  expect_calibrated(result, {8, 16});
}

// The self-check's promise at every scale of a 32×32 pyramid (8, 16 and 32 px): twice the
// reported MDB of the brightest block, and of the centre block, is found in (nearly) every seed
// (predicted > 0.99; 5 misses or more in 40 seeds have probability < 1e-4 at each of the 6).
TEST(TileCalibration, TwiceTheMdbIsFoundAtEveryScale) {
  TileCalibrationOptions options;
  options.scenes = {"cornell"};
  options.params = {{"resolution", "32"}};
  options.samples = 1;
  options.replicates = 8;
  options.seeds = 40;
  options.bias_multipliers = {2.0};
  const TileCalibrationResult result = calibrate_tiles(options);
  ASSERT_EQ(result.power.size(), 6u);
  for (const TilePowerCurve& curve : result.power) {
    const std::string where = curve.block_rule + " at " + std::to_string(curve.block) + " px";
    ASSERT_EQ(curve.points.size(), 1u);
    const BlockPowerPoint& p = curve.points.front();
    EXPECT_GT(p.predicted_power, 0.99) << where;
    EXPECT_GE(p.block_detections, 36u) << where;
    EXPECT_GE(p.detections, p.block_detections) << where;
  }
  EXPECT_EQ(result.power[2].block, 32u);
  EXPECT_EQ(result.power[2].tests, 3u);  // the whole image
}

// The calibration can fail: the light vertex cache normalised by vertices instead of paths is
// biased everywhere, so its comparisons reject in nearly every seed, overall and through every
// scale (the pass threshold would allow at most ~14 of 100 at α = 0.05), and the honest row
// beside it still passes.
TEST(TileCalibration, BiasedControlFails) {
  TileCalibrationOptions options = short_options();
  options.estimators = {"pt", "ctl-scene-lvc-per-vertex"};
  options.seeds = 40;
  options.bias_multipliers = {};
  const TileCalibrationResult result = calibrate_tiles(options);
  ASSERT_EQ(result.rows.size(), 3u);
  const TileSizeRow& honest = result.rows[0];
  EXPECT_EQ(honest.estimator_a, "pt");
  EXPECT_FALSE(honest.biased);
  EXPECT_TRUE(honest.pass);
  print_tile_calibration(result, std::cout);
  for (const TileSizeRow* row : {&result.rows[1], &result.rows[2]}) {
    expect_scale_rows(*row, {8, 16}, 40, options.test_alpha);
    EXPECT_TRUE(row->biased) << row->scene;
    EXPECT_FALSE(row->pass) << row->scene;
    EXPECT_LT(row->binomial_upper_p_value, 1e-6) << row->scene;
    EXPECT_GT(row->false_alarms, row->seeds / 2) << row->scene;
    // Biased everywhere: every scale sees it, the tiles as the whole image.
    for (const ScaleSizeRow& scale : row->scales) {
      EXPECT_FALSE(scale.pass) << row->scene << " " << scale.block << " px";
      EXPECT_GT(scale.false_alarms, scale.seeds / 2) << row->scene << " " << scale.block << " px";
    }
  }
  EXPECT_FALSE(result.pass);
  EXPECT_TRUE(result.power.empty());
}

// The verify layer's counting on made-up seeds: a false alarm is a p <= alpha, overall and
// through each scale, with the rate's Wilson interval and the binomial tests against alpha.
TEST(TileCalibration, SizeRowCountsMadeUpSeeds) {
  // Per seed: the comparison's p, then its 8 px and its 16 px scale's smallest adjusted p.
  const std::vector<std::array<double, 3>> p = {
      {0.01, 0.01, 1.0}, {0.5, 0.6, 0.5}, {0.05, 1.0, 0.05}, {0.2, 0.3, 0.2}};
  std::vector<SizeSeed> seeds;
  for (const std::array<double, 3>& q : p) {
    SizeSeed seed{.min_p_adjusted = q[0], .tests = 15};
    seed.scales.push_back({.block = 8,
                           .tests = 12,
                           .min_p_adjusted = q[1],
                           .bright_relative_mdb = 0.1,
                           .centre = {.channel = 1, .p_value = q[1]}});
    seed.scales.push_back({.block = 16,
                           .tests = 3,
                           .min_p_adjusted = q[2],
                           .bright_relative_mdb = 0.05,
                           .centre = {.channel = 1, .p_value = q[2]}});
    seeds.push_back(seed);
  }
  const PyramidSizeRow row = pyramid_size_row(seeds, 0.05, 1e-3);
  EXPECT_EQ(row.seeds, 4u);
  EXPECT_EQ(row.tests, 15u);
  EXPECT_EQ(row.false_alarms, 2u);  // 0.01 and 0.05: p <= alpha
  EXPECT_DOUBLE_EQ(row.false_alarm_rate, 0.5);
  EXPECT_DOUBLE_EQ(row.expected_false_alarms, 0.2);
  EXPECT_DOUBLE_EQ(row.wilson_low, wilson_interval(2, 4, 0.95).low);
  EXPECT_DOUBLE_EQ(row.wilson_high, wilson_interval(2, 4, 0.95).high);
  EXPECT_DOUBLE_EQ(row.binomial_upper_p_value, binomial_upper_p_value(2, 4, 0.05));
  EXPECT_DOUBLE_EQ(row.binomial_p_value, binomial_test_p_value(2, 4, 0.05));
  ASSERT_EQ(row.scales.size(), 2u);
  EXPECT_EQ(row.scales[0].false_alarms, 1u);
  EXPECT_EQ(row.scales[1].false_alarms, 1u);
  EXPECT_EQ(row.scales[1].block, 16u);
  EXPECT_EQ(row.scales[1].tests, 3u);
  EXPECT_DOUBLE_EQ(row.scales[0].expected_share, 0.025);
  EXPECT_DOUBLE_EQ(row.scales[1].expected_false_alarms, 0.1);
  EXPECT_DOUBLE_EQ(row.scales[0].median_bright_relative_mdb, 0.1);
  EXPECT_EQ(row.scales[1].centre_p_values, (std::vector<double>{1.0, 0.5, 0.05, 0.2}));
  EXPECT_EQ(row.scales[1].min_p_adjusted, (std::vector<double>{1.0, 0.5, 0.05, 0.2}));
  // 2 alarms of 4 at alpha = 0.05: P(X >= 2) = 0.014 passes a threshold of 1e-3, not of 0.05.
  EXPECT_TRUE(row.pass == (row.scales[0].pass && row.scales[1].pass));
  EXPECT_FALSE(pyramid_size_row(seeds, 0.05, 0.05).pass);
  seeds[1].scales.pop_back();
  EXPECT_THROW(pyramid_size_row(seeds, 0.05, 1e-3), std::invalid_argument);
}

// Made-up replicate images: R values per pixel, 1 + 0.2 u with u uniform from a fixed LCG.
std::vector<Image> noise_images(std::uint32_t size, std::uint32_t replicates, std::uint64_t state) {
  std::vector<Image> out;
  for (std::uint32_t r = 0; r < replicates; ++r) {
    Image image(size, size);
    for (double& v : image.values) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      v = 1.0 + 0.2 * static_cast<double>(state >> 11) * 0x1.0p-53;
    }
    out.push_back(std::move(image));
  }
  return out;
}

// What the power prediction rests on: k × the reported MDB of a block moves that block's
// statistic by exactly k m (its spread is unchanged), at every scale and by either rule; the
// block's detection is its own raw p at the scale's share; at k = 1 the prediction is 0.8.
TEST(TileCalibration, OwnMdbMovesTheStatisticByKm) {
  const std::vector<Image> a = noise_images(32, 6, 1), b = noise_images(32, 6, 2);
  const PyramidResult t = compare_blocks(a, b, 0.05);
  ASSERT_EQ(t.scales.size(), 3u);
  const std::vector<double> ks = {0.5, 1.0, 2.0};
  for (std::size_t s = 0; s < t.scales.size(); ++s) {
    for (const InjectionRule rule : {InjectionRule::kBrightest, InjectionRule::kCentre}) {
      std::vector<PyramidResult> seen;
      const Retest retest = [&](const std::vector<Image>& biased) {
        seen.push_back(compare_blocks(biased, b, 0.05));
        return seen.back();
      };
      const InjectionSeed p = inject_own_mdb(t, s, rule, a, retest, ks, 0.05);
      const std::string where = std::string(rule_name(rule)) + " at scale " + std::to_string(s);
      ASSERT_EQ(seen.size(), ks.size()) << where;
      const std::vector<BlockTest>& tests = t.scales[s].tests;
      const auto it = std::find_if(tests.begin(), tests.end(), [&](const BlockTest& x) {
        return x.x == p.block.x && x.y == p.block.y && x.channel == p.block.channel;
      });
      ASSERT_NE(it, tests.end()) << where;
      const std::size_t index = static_cast<std::size_t>(it - tests.begin());
      EXPECT_EQ(p.share, t.scales[s].detection_share) << where;
      EXPECT_EQ(p.mdb, it->min_detectable_bias) << where;
      if (rule == InjectionRule::kCentre) {
        EXPECT_EQ(p.block.channel, kCentreChannel) << where;
      } else {
        EXPECT_EQ(&*it, &brightest_block(t.scales[s])) << where;
      }
      for (std::size_t j = 0; j < ks.size(); ++j) {
        const BlockTest& shifted = seen[j].scales[s].tests[index];
        EXPECT_NEAR(shifted.statistic, it->statistic + ks[j] * p.multiplier, 1e-6) << where;
        EXPECT_EQ(p.block_detected[j], shifted.p_value <= p.share) << where;
        EXPECT_EQ(p.detected[j], seen[j].rejected) << where;
      }
      EXPECT_NEAR(p.predicted[1], 0.8, 1e-4) << where;
    }
  }
}

TileCalibrationOptions tiny_options() {
  TileCalibrationOptions options;
  options.params = {{"resolution", "16"}};
  options.samples = 1;
  options.replicates = 4;
  options.seeds = 8;
  options.first_seed = 5;
  return options;
}

nlohmann::ordered_json without_timing(nlohmann::ordered_json j) {
  j.erase("wall_seconds");
  return j;
}

// The same numbers for any thread count (seeds in parallel, each into its own slot); another
// first seed gives other numbers, and seed s's numbers whatever the first seed.
TEST(TileCalibration, DeterministicForAnyThreadCount) {
  const TileCalibrationResult all = calibrate_tiles(tiny_options());
  TileCalibrationResult one;
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = calibrate_tiles(tiny_options());
  }
  EXPECT_EQ(without_timing(tile_calibration_json(all)).dump(),
            without_timing(tile_calibration_json(one)).dump());
  std::ostringstream text_all, text_one;
  print_tile_calibration(all, text_all);
  print_tile_calibration(one, text_one);
  EXPECT_EQ(text_all.str(), text_one.str());

  TileCalibrationOptions shifted = tiny_options();
  shifted.first_seed = 6;
  const TileCalibrationResult next = calibrate_tiles(shifted);
  for (std::size_t r = 0; r < all.rows.size(); ++r) {
    const std::vector<double>& a = all.rows[r].min_p_adjusted;
    const std::vector<double>& b = next.rows[r].min_p_adjusted;
    EXPECT_EQ(std::vector<double>(a.begin() + 1, a.end()),
              std::vector<double>(b.begin(), b.end() - 1));
  }
}

nlohmann::json load_schema() {
  std::ifstream in(std::string(PCBENCH_SOURCE_DIR) + "/results/report.schema.json");
  return nlohmann::json::parse(in);
}

// Every field the schema requires is written, and every field written is documented there.
void expect_fields_match(const nlohmann::ordered_json& object, const nlohmann::json& definition,
                         const std::string& where) {
  ASSERT_TRUE(object.is_object()) << where;
  for (const auto& key : definition.at("required")) {
    EXPECT_TRUE(object.contains(key.get<std::string>())) << where << ": missing " << key;
  }
  for (const auto& [key, value] : object.items()) {
    EXPECT_TRUE(definition.at("properties").contains(key)) << where << ": undocumented " << key;
  }
}

TEST(TileCalibration, JsonHasTheDocumentedFields) {
  const TileCalibrationResult result = calibrate_tiles(tiny_options());
  const nlohmann::ordered_json j = tile_calibration_json(result);
  const nlohmann::json schema = load_schema();
  const nlohmann::json& defs = schema.at("$defs");
  ASSERT_TRUE(schema.at("properties").contains("tile_calibration"));
  expect_fields_match(j, defs.at("tileCalibration"), "tile_calibration");
  ASSERT_EQ(j.at("rows").size(), 3u);
  for (const auto& row : j.at("rows")) {
    expect_fields_match(row, defs.at("tileSizeRow"), "rows");
    EXPECT_EQ(row.at("min_p_adjusted").size(), 8u);
    ASSERT_EQ(row.at("scales").size(), 2u);  // 8 px and 16 px, the whole image
    for (const auto& scale : row.at("scales")) {
      expect_fields_match(scale, defs.at("tileScaleSizeRow"), "scales");
      expect_fields_match(scale.at("centre_block"),
                          defs.at("tileScaleSizeRow").at("properties").at("centre_block"),
                          "centre_block");
      EXPECT_EQ(scale.at("min_p_adjusted").size(), 8u);
    }
    EXPECT_EQ(row.at("scales")[0].at("tests"), 12);
    EXPECT_EQ(row.at("scales")[1].at("tests"), 3);
    EXPECT_EQ(row.at("scales")[1].at("block"), 16);
  }
  // cornell's first pair: the brightest block at 8 and 16 px, then the centre block.
  ASSERT_EQ(j.at("power_curves").size(), 4u);
  for (const auto& curve : j.at("power_curves")) {
    expect_fields_match(curve, defs.at("tilePowerCurve"), "power_curves");
    ASSERT_EQ(curve.at("points").size(), 3u);
    for (const auto& p : curve.at("points")) {
      expect_fields_match(p, defs.at("tilePowerPoint"), "points");
    }
    for (const auto& b : curve.at("injected_blocks")) {
      expect_fields_match(
          b, defs.at("tilePowerCurve").at("properties").at("injected_blocks").at("items"),
          "injected_blocks");
    }
  }
  const auto& curve = j.at("power_curves")[0];
  EXPECT_EQ(j.at("rows")[0].at("run_b"), "exact");
  EXPECT_EQ(j.at("rows")[2].at("estimator_a"), "pt");
  EXPECT_EQ(j.at("rows")[2].at("estimator_b"), "plain");
  EXPECT_EQ(curve.at("estimator_a"), "pt");
  EXPECT_EQ(curve.at("block_rule"), "brightest");
  EXPECT_EQ(curve.at("block"), 8);
  EXPECT_EQ(j.at("power_curves")[1].at("block"), 16);
  EXPECT_EQ(j.at("power_curves")[2].at("block_rule"), "centre");
  EXPECT_EQ(j.at("first_seed"), 5);
  EXPECT_EQ(j.at("pass"), result.pass);
}

TEST(TileCalibration, BadOptionsAreInputErrors) {
  const auto fails = [](TileCalibrationOptions options) {
    EXPECT_THROW(calibrate_tiles(options), InputError);
  };
  TileCalibrationOptions o = tiny_options();
  o.scenes = {"genz-gaussian"};  // not a scene
  fails(o);
  o = tiny_options();
  o.scenes = {"cornell", "cornell"};
  fails(o);
  o = tiny_options();
  o.estimators = {"pt"};  // cornell is compared pairwise
  fails(o);
  // Light tracing cannot sample the paths through a mirror: comparing it there would differ
  // without a fault in either estimator.
  const TemporaryFolder folder;
  write_text(folder.path() / "mirror.json", R"({
    "camera": {"position": [0, 1, 3], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov": 40},
    "materials": {"white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
                  "glass": {"type": "mirror", "albedo": [0.9, 0.9, 0.9]}},
    "shapes": [
      {"type": "box", "min": [-2, 0, -2], "max": [2, 3, 4], "material": "white",
       "normals": "inward"},
      {"type": "quad", "corners": [[-1, 2.9, -1], [1, 2.9, -1], [1, 2.9, 1], [-1, 2.9, 1]],
       "material": "white", "emission": [4, 4, 4]},
      {"type": "triangle", "corners": [[-1, 0, -1.5], [1, 0, -1.5], [0, 2, -1.5]],
       "material": "glass"}]
  })");
  o = tiny_options();
  o.estimators = {"plain", "lt"};
  o.scenes = {(folder.path() / "mirror.json").string()};
  fails(o);
  o = tiny_options();
  o.bias_multipliers = {1.0, 0.0};
  fails(o);
  o = tiny_options();
  o.replicates = 1;
  fails(o);
  o = tiny_options();
  o.params = {{"nobody_reads_this", "1"}};
  fails(o);
  EXPECT_THROW(is_scene_name("no-such-scene"), InputError);
  EXPECT_TRUE(is_scene_name("furnace"));
  EXPECT_FALSE(is_scene_name("genz-gaussian"));
  // The furnace alone needs one estimator only: it has an exact image.
  o = tiny_options();
  o.estimators = {"pt"};
  o.scenes = {"furnace"};
  o.seeds = 2;
  const TileCalibrationResult furnace = calibrate_tiles(o);
  EXPECT_EQ(furnace.rows.size(), 1u);
  EXPECT_TRUE(furnace.power.empty());
}

// The full form: the defaults (32×32, 4 spp × 8 replicates, 1000 seeds; 3 scales). Same checks
// and error budget as the short form. Prints the tables quoted in
// docs/findings/tile-calibration.md.
TEST(TileCalibrationFull, DefaultOptions) {
  const TileCalibrationResult result = calibrate_tiles({});
  print_tile_calibration(result, std::cout);
  std::cout << "calibrate_tiles() took " << result.wall_seconds << " s\n";
  expect_calibrated(result, {8, 16, 32});
}

}  // namespace
}  // namespace pcbench
