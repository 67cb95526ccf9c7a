#include "harness/commands/tile_calibration.h"

#include <fmt/format.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <set>
#include <span>
#include <stdexcept>
#include <tuple>

#include "base/errors.h"
#include "estimators/scene/scene_estimator.h"
#include "harness/commands/calibration.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/session/report.h"
#include "harness/verify/block_checks.h"
#include "harness/verify/block_pyramid.h"
#include "harness/verify/image_statistics.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kConfidence = 0.95;  // of the Wilson intervals
// The fixed tile (KS test, centre-tile power curve): the one holding the image centre, in this
// channel. Any choice made before the samples are seen would do; it must not be black (its
// p-value would be 1 in every seed), and green at the centre is lit in every built-in scene.
constexpr std::uint32_t kFixedChannel = 1;

using Json = nlohmann::ordered_json;

// One comparison of the calibration: estimator a against estimator b on a scene, or against the
// scene's exact image (b < 0).
struct ComparisonSpec {
  std::size_t scene = 0;
  std::size_t a = 0;
  int b = -1;
};

struct ScenePlans {
  const SceneIntegrand* integrand = nullptr;
  std::optional<Image> exact;
  std::vector<const RunPlan*> runs;  // in the order of options.estimators
};

// Which tile×channel test a power curve's bias goes into, per seed.
enum class InjectionRule {
  kBrightest,  // brightest_tile: the session's self-check, chosen from the same sample
  kCentre,     // the fixed tile at the image centre: chosen before any sample is seen
};

struct CurveSpec {
  std::size_t row = 0;  // the comparison
  InjectionRule rule = InjectionRule::kBrightest;
};

// What a power curve needs of one seed.
struct PowerSeed {
  std::size_t tile_index = 0;  // into ScaleTests::tiles
  BlockTest tile = {};         // the injected tile as the unbiased comparison saw it
  double mdb = kNaN, stderr_of_difference = kNaN, multiplier = kNaN;
  std::vector<bool> detected, tile_detected;              // per k: k × this seed's MDB
  std::vector<double> predicted;                          // per k
  std::vector<bool> fixed_detected, fixed_tile_detected;  // per k: the fixed δ_k
  // For the fixed δ, which is known only once every seed has its MDB: the injected tile cut out
  // of a's and b's replicates, and the smallest raw p of the comparison's other tests (which a
  // bias in this tile×channel does not change). Kept instead of whole images, whose memory
  // would grow with seeds × pixels.
  std::vector<Image> crop_a, crop_b;
  double other_min_p = 1.0;
};

// What a size row needs of one seed's comparison.
struct RowSeed {
  double min_p_adjusted = kNaN;
  double bright_relative_mdb = kNaN;
  std::uint32_t tests = 0;
  BlockTest fixed = {};  // the centre tile's test, whose p-values are KS-tested
};

struct SeedOutcome {
  std::vector<RowSeed> rows;     // per comparison
  std::vector<PowerSeed> power;  // per curve
};

// The tile tests alone: the finest scale of the block pyramid, decided as a family of its own.
ScaleTests compare_tiles(std::span<const Image> a, std::span<const Image> b, double alpha) {
  return compare_blocks(a, b, alpha, {.max_scales = 1}).scales.front();
}
ScaleTests test_tiles_against_exact(std::span<const Image> a, const Image& exact, double alpha) {
  return test_blocks_against_exact(a, exact, alpha, {.max_scales = 1}).scales.front();
}

// NaN when some value is (an unknown detectable bias must not read as a small one).
double median(std::vector<double> values) {
  if (values.empty() ||
      std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); })) {
    return kNaN;
  }
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The test of the tile holding the image centre, in kFixedChannel.
const BlockTest& centre_tile(const ScaleTests& t, std::uint32_t width, std::uint32_t height) {
  const std::uint32_t size = PyramidOptions{}.tile;
  const std::uint32_t tx = (width / 2) / size, ty = (height / 2) / size;
  const auto it = std::find_if(t.tests.begin(), t.tests.end(), [&](const BlockTest& x) {
    return x.x == tx && x.y == ty && x.channel == kFixedChannel;
  });
  if (it == t.tests.end()) throw std::logic_error("tile calibration: no centre tile");
  return *it;
}

// The injected tile's own test rejects at Holm's first threshold (which the MDB is computed at).
bool tile_rejects(const ScaleTests& t, std::size_t index, double share) {
  return t.tests.at(index).p_value <= share;
}

void validate(const TileCalibrationOptions& o) {
  const std::string where = "tile calibration";
  const auto unique = [&](const std::vector<std::string>& names, const char* what) {
    if (names.empty()) throw InputError(fmt::format("{}: no {} given", where, what));
    std::set<std::string> seen;
    for (const std::string& name : names) {
      if (!seen.insert(name).second) {
        throw InputError(fmt::format("{}: {} '{}' is listed twice", where, what, name));
      }
    }
  };
  unique(o.estimators, "estimator");
  unique(o.scenes, "scene");
  for (const std::string& name : o.scenes) {
    if (!is_scene_name(name)) {
      throw InputError(fmt::format(
          "{}: '{}' is not a scene (the tile test is calibrated on scenes; `pcbench calibrate` "
          "on an analytic integrand calibrates the run test)",
          where, name));
    }
  }
  if (o.seeds < 2) throw InputError(where + ": seeds must be at least 2");
  if (o.replicates < 2) throw InputError(where + ": replicates must be at least 2");
  if (o.first_seed > std::numeric_limits<std::uint64_t>::max() - o.seeds) {
    throw InputError(where + ": first_seed + seeds overflows");
  }
  if (!(o.test_alpha > 0.0 && o.test_alpha < 1.0)) {
    throw InputError(fmt::format("{}: test_alpha must be in (0, 1), not {}", where, o.test_alpha));
  }
  if (!(o.pass_threshold > 0.0 && o.pass_threshold <= 1.0)) {
    throw InputError(
        fmt::format("{}: pass_threshold must be in (0, 1], not {}", where, o.pass_threshold));
  }
  for (double k : o.bias_multipliers) {
    if (!(std::isfinite(k) && k > 0.0)) {
      throw InputError(fmt::format("{}: bias multiplier {} is not a positive number", where, k));
    }
  }
}

// One plan per scene and estimator, from one grid: a key of `params` needs only one reader.
std::vector<ScenePlans> plan_scenes(const TileCalibrationOptions& options,
                                    std::vector<RunPlan>& plans) {
  GridRequest grid{.estimators = options.estimators,
                   .integrands = options.scenes,
                   .samples = options.samples,
                   .replicates = options.replicates,
                   .where = "tile calibration"};
  for (const auto& [key, value] : options.params) grid.params[key] = {value};
  plans = plan_runs({grid}, {.samples = options.samples, .replicates = options.replicates});
  std::vector<ScenePlans> scenes(options.scenes.size());
  for (std::size_t s = 0; s < options.scenes.size(); ++s) {
    for (const std::string& estimator : options.estimators) {
      const auto it = std::find_if(plans.begin(), plans.end(), [&](const RunPlan& p) {
        return p.estimator->name == estimator && p.integrand->name == options.scenes[s];
      });
      if (it == plans.end()) throw std::logic_error("tile calibration: a run was not planned");
      scenes[s].runs.push_back(&*it);
    }
    scenes[s].integrand =
        dynamic_cast<const SceneIntegrand*>(scenes[s].runs.front()->made_integrand.get());
    if (!scenes[s].integrand) throw std::logic_error("tile calibration: not a scene integrand");
    scenes[s].exact = exact_image(*scenes[s].integrand);
  }
  return scenes;
}

// Per scene in order: each estimator against the exact image where there is one, else every
// pair of estimators (which must both sample every path of the scene, as in a session).
std::vector<ComparisonSpec> comparison_specs(const TileCalibrationOptions& options,
                                             const std::vector<ScenePlans>& scenes) {
  std::vector<ComparisonSpec> specs;
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    const ScenePlans& scene = scenes[s];
    if (scene.exact) {
      for (std::size_t a = 0; a < options.estimators.size(); ++a) specs.push_back({s, a, -1});
      continue;
    }
    if (options.estimators.size() < 2) {
      throw InputError(fmt::format(
          "tile calibration: scene '{}' has no exact image, so its runs are compared pairwise: "
          "give at least two estimators",
          options.scenes[s]));
    }
    for (const RunPlan* plan : scene.runs) {
      if (!plan->render->samples_all_paths(scene.integrand->scene())) {
        throw InputError(fmt::format(
            "tile calibration: {} cannot sample every path of '{}', so a comparison with another "
            "estimator there would differ without a fault in either",
            plan->estimator->name, options.scenes[s]));
      }
    }
    for (std::size_t a = 0; a < options.estimators.size(); ++a) {
      for (std::size_t b = a + 1; b < options.estimators.size(); ++b) {
        specs.push_back({s, a, static_cast<int>(b)});
      }
    }
  }
  return specs;
}

// One run's replicate images at `seed`.
std::vector<Image> render(const RunPlan& plan, std::uint64_t seed,
                          const std::atomic<bool>* interrupted) {
  RunResult run = execute_run(plan, {.seed = seed, .interrupted = interrupted});
  if (run.status == RunStatus::kNotRun) throw CalibrationInterrupted();
  if (run.status != RunStatus::kOk) {
    throw std::runtime_error(
        fmt::format("tile calibration: {} on {} with seed {} did not finish: {}",
                    plan.estimator->name, plan.integrand->name, seed,
                    run.error.empty() ? std::string("non-finite pixels") : run.error));
  }
  return std::move(run.images);
}

// The pixels of `tile` in every image: a tile_size × tile_size image (less at the border).
std::vector<Image> crop(const std::vector<Image>& images, const BlockTest& tile) {
  const std::uint32_t size = PyramidOptions{}.tile;
  std::vector<Image> out;
  for (const Image& image : images) {
    const std::uint32_t x0 = tile.x * size, y0 = tile.y * size;
    Image c(std::min(size, image.width - x0), std::min(size, image.height - y0));
    for (std::uint32_t y = 0; y < c.height; ++y) {
      for (std::uint32_t x = 0; x < c.width; ++x) {
        for (std::uint32_t ch = 0; ch < kImageChannels; ++ch) {
          c.at(x, y, ch) = image.at(x0 + x, y0 + y, ch);
        }
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

struct Decision {
  bool tile = false;    // the injected tile's raw p <= share
  bool family = false;  // the comparison rejects
  double tile_p = 1.0;
};

// The comparison with `bias` in the injected tile, decided from the kept crops: the tile's test
// is compare_tiles' own on the crop (its tile means sum the same pixels in the same order), and
// the comparison rejects when Holm's smallest adjusted p, min(1, T × the smallest raw p), is
// <= α. inject_own_mdb checks on every seed that this is the whole comparison's decision.
Decision decide_on_crop(const PowerSeed& p, double bias, std::uint32_t tests, double share,
                        double alpha) {
  BlockTest local = p.tile;
  local.x = local.y = 0;
  const ScaleTests t =
      compare_tiles(with_block_bias(p.crop_a, local, PyramidOptions{}.tile, bias), p.crop_b, alpha);
  Decision d;
  d.tile_p = t.tests.at(p.tile.channel).p_value;
  d.tile = d.tile_p <= share;
  d.family = std::min(1.0, std::min(p.other_min_p, d.tile_p) * static_cast<double>(tests)) <= alpha;
  return d;
}

// k × the seed's own reported MDB of tile `index` into a's images, for every k.
PowerSeed inject_own_mdb(const ScaleTests& t, std::size_t index, const std::vector<Image>& a,
                         const std::vector<Image>& b, const TileCalibrationOptions& options) {
  // The comparison is decided alone, so its tile threshold is Holm's first, α / T, and the
  // reported MDB is m × the tile's standard error with m at that threshold.
  const double share = options.test_alpha / static_cast<double>(t.tests.size());
  PowerSeed p;
  p.tile_index = index;
  p.tile = t.tests.at(index);
  const BlockTest& tile = p.tile;
  p.mdb = tile.min_detectable_bias;
  p.multiplier = detectable_multiplier(share, tile.dof, PyramidOptions{}.power);
  p.stderr_of_difference = p.mdb / p.multiplier;
  // The MDB must be the one this decision implies, the statistic's own standard error times m;
  // otherwise the power below would be predicted for another threshold.
  if (tile.statistic != 0.0 && std::isfinite(tile.statistic) && std::isfinite(p.mdb)) {
    const double se = (tile.mean_a - tile.mean_b) / tile.statistic;
    if (!(std::fabs(se - p.stderr_of_difference) <= 1e-9 * se)) {
      throw std::logic_error(
          fmt::format("tile calibration: the reported MDB {} is not m(alpha/T = {}) x stderr {}",
                      p.mdb, share, se));
    }
  }
  p.crop_a = crop(a, tile);
  p.crop_b = crop(b, tile);
  for (std::size_t k = 0; k < t.tests.size(); ++k) {
    if (k != index) p.other_min_p = std::min(p.other_min_p, t.tests[k].p_value);
  }
  for (const double k : options.bias_multipliers) {
    const ScaleTests shifted = compare_tiles(
        with_block_bias(a, tile, PyramidOptions{}.tile, k * p.mdb), b, options.test_alpha);
    p.detected.push_back(shifted.min_p_adjusted <= options.test_alpha);
    p.tile_detected.push_back(tile_rejects(shifted, index, share));
    // A tile known exactly detects any bias.
    p.predicted.push_back(p.mdb > 0.0 ? shifted_t_power(k * p.multiplier, tile.dof, share) : 1.0);
    const Decision cropped = decide_on_crop(
        p, k * p.mdb, static_cast<std::uint32_t>(t.tests.size()), share, options.test_alpha);
    if (cropped.tile_p != shifted.tests[index].p_value ||
        cropped.family != (shifted.min_p_adjusted <= options.test_alpha)) {
      throw std::logic_error("tile calibration: the cropped tile does not decide as the image");
    }
  }
  return p;
}

// Fills a row's counts and tests from its per-seed values.
void test_row(TileSizeRow& row, const TileCalibrationOptions& o) {
  row.seeds = static_cast<std::uint32_t>(row.min_p_adjusted.size());
  row.false_alarms =
      static_cast<std::uint64_t>(std::count_if(row.min_p_adjusted.begin(), row.min_p_adjusted.end(),
                                               [&](double p) { return p <= o.test_alpha; }));
  row.expected_false_alarms = static_cast<double>(row.seeds) * o.test_alpha;
  row.false_alarm_rate = static_cast<double>(row.false_alarms) / row.seeds;
  const ProportionInterval ci = wilson_interval(row.false_alarms, row.seeds, kConfidence);
  row.wilson_low = ci.low;
  row.wilson_high = ci.high;
  row.binomial_p_value = binomial_test_p_value(row.false_alarms, row.seeds, o.test_alpha);
  row.binomial_upper_p_value = binomial_upper_p_value(row.false_alarms, row.seeds, o.test_alpha);
  row.fixed_tile_ks = ks_uniform(row.fixed_tile_p_values);
  row.pass = row.binomial_upper_p_value >= o.pass_threshold &&
             row.fixed_tile_ks.p_value >= o.pass_threshold;
}

TileSizeRow size_row(const ComparisonSpec& spec, std::size_t r,
                     const std::vector<ScenePlans>& scenes,
                     const std::vector<SeedOutcome>& outcomes,
                     const TileCalibrationOptions& options) {
  const ScenePlans& scene = scenes[spec.scene];
  const scene::SceneDescription& d = scene.integrand->scene().description();
  TileSizeRow row;
  row.scene = options.scenes[spec.scene];
  row.width = d.width;
  row.height = d.height;
  const RunPlan& a = *scene.runs[spec.a];
  row.estimator_a = a.estimator->name;
  row.run_a = a.id;
  row.biased = a.estimator->biased;
  if (spec.b < 0) {
    row.estimator_b = row.run_b = "exact";
  } else {
    const RunPlan& b = *scene.runs[static_cast<std::size_t>(spec.b)];
    row.estimator_b = b.estimator->name;
    row.run_b = b.id;
    row.biased = row.biased || b.estimator->biased;
  }
  const RowSeed& first = outcomes.front().rows[r];
  row.tests = first.tests;
  row.fixed_tile_x = first.fixed.x;
  row.fixed_tile_y = first.fixed.y;
  row.fixed_channel = first.fixed.channel;
  std::vector<double> bright;
  for (const SeedOutcome& o : outcomes) {
    row.min_p_adjusted.push_back(o.rows[r].min_p_adjusted);
    row.fixed_tile_p_values.push_back(o.rows[r].fixed.p_value);
    bright.push_back(o.rows[r].bright_relative_mdb);
  }
  row.median_bright_relative_mdb = median(std::move(bright));
  test_row(row, options);
  return row;
}

// A curve's summary of its injected tiles over the seeds (not yet its points).
TilePowerCurve power_curve(const CurveSpec& spec, std::size_t c, const TileSizeRow& row,
                           const std::vector<SeedOutcome>& outcomes, double test_alpha) {
  TilePowerCurve curve;
  curve.scene = row.scene;
  curve.width = row.width;
  curve.height = row.height;
  curve.estimator_a = row.estimator_a;
  curve.estimator_b = row.estimator_b;
  curve.run_a = row.run_a;
  curve.run_b = row.run_b;
  curve.tile_rule = spec.rule == InjectionRule::kBrightest ? "brightest" : "centre";
  curve.seeds = static_cast<std::uint32_t>(outcomes.size());
  curve.tests = row.tests;
  curve.share = test_alpha / static_cast<double>(row.tests);
  std::vector<double> mdbs, dofs, relative;
  double se2 = 0.0, statistic = 0.0;
  std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, std::uint32_t> tiles;
  for (const SeedOutcome& o : outcomes) {
    const PowerSeed& p = o.power[c];
    mdbs.push_back(p.mdb);
    dofs.push_back(p.tile.dof);
    const double tile_mean = 0.5 * (p.tile.mean_a + p.tile.mean_b);
    if (tile_mean > 0.0) relative.push_back(p.mdb / tile_mean);
    se2 += p.stderr_of_difference * p.stderr_of_difference;
    statistic += p.tile.statistic;
    ++tiles[{p.tile.x, p.tile.y, p.tile.channel}];
  }
  const double seeds = static_cast<double>(outcomes.size());
  curve.median_mdb = median(mdbs);
  curve.median_dof = median(dofs);
  curve.median_relative_mdb = median(relative);
  curve.rms_stderr = std::sqrt(se2 / seeds);
  curve.mean_statistic = statistic / seeds;
  for (const auto& [key, count] : tiles) {
    curve.injected_tiles.push_back({std::get<0>(key), std::get<1>(key), std::get<2>(key), count});
  }
  std::stable_sort(curve.injected_tiles.begin(), curve.injected_tiles.end(),
                   [](const InjectedTile& x, const InjectedTile& y) { return x.seeds > y.seeds; });
  return curve;
}

// The curve's points from the seeds' detections.
void count_points(TilePowerCurve& curve, std::size_t c, const std::vector<SeedOutcome>& outcomes,
                  const TileCalibrationOptions& options) {
  const auto rate = [&](std::uint32_t count, double& value, double& low, double& high) {
    value = static_cast<double>(count) / curve.seeds;
    const ProportionInterval ci = wilson_interval(count, curve.seeds, kConfidence);
    low = ci.low;
    high = ci.high;
  };
  for (std::size_t j = 0; j < options.bias_multipliers.size(); ++j) {
    TilePowerPoint point;
    point.multiplier = options.bias_multipliers[j];
    point.fixed_bias = point.multiplier * curve.median_mdb;
    double predicted = 0.0;
    for (const SeedOutcome& o : outcomes) {
      const PowerSeed& p = o.power[c];
      point.detections += p.detected[j] ? 1 : 0;
      point.tile_detections += p.tile_detected[j] ? 1 : 0;
      point.fixed_detections += p.fixed_detected[j] ? 1 : 0;
      point.fixed_tile_detections += p.fixed_tile_detected[j] ? 1 : 0;
      predicted += p.predicted[j];
    }
    rate(point.detections, point.detection_rate, point.wilson_low, point.wilson_high);
    rate(point.tile_detections, point.tile_detection_rate, point.tile_wilson_low,
         point.tile_wilson_high);
    rate(point.fixed_detections, point.fixed_detection_rate, point.fixed_wilson_low,
         point.fixed_wilson_high);
    rate(point.fixed_tile_detections, point.fixed_tile_detection_rate, point.fixed_tile_wilson_low,
         point.fixed_tile_wilson_high);
    point.predicted_power = predicted / curve.seeds;
    point.fixed_predicted_power =
        curve.rms_stderr > 0.0
            ? noncentral_t_power(point.fixed_bias / curve.rms_stderr, curve.median_dof, curve.share)
            : 1.0;
    curve.points.push_back(point);
  }
}

double elapsed_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

bool is_scene_name(const std::string& integrand) {
  return find_integrand(integrand).has_tag("scene");
}

TileCalibrationResult calibrate_tiles(const TileCalibrationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  validate(options);
  TileCalibrationResult result;
  result.options = options;
  std::vector<RunPlan> plans;
  const std::vector<ScenePlans> scenes = plan_scenes(options, plans);
  const std::vector<ComparisonSpec> specs = comparison_specs(options, scenes);
  // The power curves: each compared scene's first pair, with the bias in the brightest tile (the
  // session's self-check) and in the fixed centre tile (no selection: the MDB's own promise).
  std::vector<CurveSpec> curves;
  if (!options.bias_multipliers.empty()) {
    for (std::size_t r = 0; r < specs.size(); ++r) {
      if (specs[r].b < 0 || (r > 0 && specs[r - 1].scene == specs[r].scene)) continue;
      for (const InjectionRule rule : {InjectionRule::kBrightest, InjectionRule::kCentre}) {
        curves.push_back({r, rule});
      }
    }
  }

  // Every seed: every run, every comparison, the per-seed-MDB injections.
  std::vector<SeedOutcome> outcomes(options.seeds);
  tbb::parallel_for(std::uint32_t{0}, options.seeds, [&](std::uint32_t i) {
    const std::uint64_t seed = options.first_seed + i;
    std::vector<std::vector<std::vector<Image>>> images(scenes.size());
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      for (const RunPlan* plan : scenes[s].runs) {
        images[s].push_back(render(*plan, seed, options.interrupted));
      }
    }
    SeedOutcome& out = outcomes[i];
    std::vector<ScaleTests> tests;
    for (const ComparisonSpec& spec : specs) {
      const std::vector<Image>& a = images[spec.scene][spec.a];
      const ScaleTests t =
          spec.b < 0 ? test_tiles_against_exact(a, *scenes[spec.scene].exact, options.test_alpha)
                     : compare_tiles(a, images[spec.scene][static_cast<std::size_t>(spec.b)],
                                     options.test_alpha);
      out.rows.push_back({.min_p_adjusted = t.min_p_adjusted,
                          .bright_relative_mdb = t.worst_bright_relative_mdb,
                          .tests = static_cast<std::uint32_t>(t.tests.size()),
                          .fixed = centre_tile(t, a.front().width, a.front().height)});
      tests.push_back(t);
    }
    for (const CurveSpec& curve : curves) {
      const ComparisonSpec& spec = specs[curve.row];
      const std::vector<Image>& a = images[spec.scene][spec.a];
      const std::vector<Image>& b = images[spec.scene][static_cast<std::size_t>(spec.b)];
      const ScaleTests& t = tests[curve.row];
      const BlockTest& tile = curve.rule == InjectionRule::kBrightest
                                  ? brightest_block(t)
                                  : centre_tile(t, a.front().width, a.front().height);
      out.power.push_back(
          inject_own_mdb(t, static_cast<std::size_t>(&tile - t.tests.data()), a, b, options));
    }
  });

  for (std::size_t r = 0; r < specs.size(); ++r) {
    result.rows.push_back(size_row(specs[r], r, scenes, outcomes, options));
  }
  result.pass = std::all_of(result.rows.begin(), result.rows.end(),
                            [](const TileSizeRow& row) { return row.pass; });

  // The fixed δ_k needs the median MDB over every seed first, then a second pass over the kept
  // crops.
  for (std::size_t c = 0; c < curves.size(); ++c) {
    TilePowerCurve curve =
        power_curve(curves[c], c, result.rows[curves[c].row], outcomes, options.test_alpha);
    tbb::parallel_for(std::uint32_t{0}, options.seeds, [&](std::uint32_t i) {
      PowerSeed& p = outcomes[i].power[c];
      for (const double k : options.bias_multipliers) {
        const Decision d =
            decide_on_crop(p, k * curve.median_mdb, curve.tests, curve.share, options.test_alpha);
        p.fixed_detected.push_back(d.family);
        p.fixed_tile_detected.push_back(d.tile);
      }
    });
    count_points(curve, c, outcomes, options);
    result.power.push_back(std::move(curve));
  }
  result.wall_seconds = elapsed_since(start);
  return result;
}

namespace {

Json number(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

Json numbers(const std::vector<double>& values) {
  Json out = Json::array();
  for (double v : values) out.push_back(number(v));
  return out;
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
  j["seeds"] = row.seeds;
  j["tests"] = row.tests;
  j["false_alarms"] = row.false_alarms;
  j["expected_false_alarms"] = number(row.expected_false_alarms);
  j["false_alarm_rate"] = number(row.false_alarm_rate);
  j["wilson_low"] = number(row.wilson_low);
  j["wilson_high"] = number(row.wilson_high);
  j["binomial_p_value"] = number(row.binomial_p_value);
  j["binomial_upper_p_value"] = number(row.binomial_upper_p_value);
  j["fixed_tile"] = {{"tile_x", row.fixed_tile_x},
                     {"tile_y", row.fixed_tile_y},
                     {"channel", row.fixed_channel},
                     {"ks_statistic", number(row.fixed_tile_ks.statistic)},
                     {"ks_p_value", number(row.fixed_tile_ks.p_value)},
                     {"p_values", numbers(row.fixed_tile_p_values)}};
  j["median_bright_relative_mdb"] = number(row.median_bright_relative_mdb);
  j["pass"] = row.pass;
  j["min_p_adjusted"] = numbers(row.min_p_adjusted);
  return j;
}

Json point_json(const TilePowerPoint& p) {
  Json j = Json::object();
  j["multiplier"] = number(p.multiplier);
  j["own_mdb"] = {{"detections", p.detections},
                  {"detection_rate", number(p.detection_rate)},
                  {"wilson_low", number(p.wilson_low)},
                  {"wilson_high", number(p.wilson_high)},
                  {"tile_detections", p.tile_detections},
                  {"tile_detection_rate", number(p.tile_detection_rate)},
                  {"tile_wilson_low", number(p.tile_wilson_low)},
                  {"tile_wilson_high", number(p.tile_wilson_high)},
                  {"predicted_power", number(p.predicted_power)}};
  j["fixed_bias"] = {{"bias", number(p.fixed_bias)},
                     {"detections", p.fixed_detections},
                     {"detection_rate", number(p.fixed_detection_rate)},
                     {"wilson_low", number(p.fixed_wilson_low)},
                     {"wilson_high", number(p.fixed_wilson_high)},
                     {"tile_detections", p.fixed_tile_detections},
                     {"tile_detection_rate", number(p.fixed_tile_detection_rate)},
                     {"tile_wilson_low", number(p.fixed_tile_wilson_low)},
                     {"tile_wilson_high", number(p.fixed_tile_wilson_high)},
                     {"predicted_power", number(p.fixed_predicted_power)}};
  return j;
}

Json curve_json(const TilePowerCurve& c) {
  Json tiles = Json::array();
  for (const InjectedTile& t : c.injected_tiles) {
    tiles.push_back(Json{
        {"tile_x", t.tile_x}, {"tile_y", t.tile_y}, {"channel", t.channel}, {"seeds", t.seeds}});
  }
  Json points = Json::array();
  for (const TilePowerPoint& p : c.points) points.push_back(point_json(p));
  return Json{{"scene", c.scene},
              {"width", c.width},
              {"height", c.height},
              {"estimator_a", c.estimator_a},
              {"estimator_b", c.estimator_b},
              {"run_a", c.run_a},
              {"run_b", c.run_b},
              {"tile_rule", c.tile_rule},
              {"seeds", c.seeds},
              {"tests", c.tests},
              {"share", number(c.share)},
              {"median_mdb", number(c.median_mdb)},
              {"median_relative_mdb", number(c.median_relative_mdb)},
              {"rms_stderr", number(c.rms_stderr)},
              {"median_dof", number(c.median_dof)},
              {"mean_statistic", number(c.mean_statistic)},
              {"injected_tiles", std::move(tiles)},
              {"points", std::move(points)}};
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
  j["tile"] = PyramidOptions{}.tile;
  j["power"] = PyramidOptions{}.power;
  j["pass_threshold"] = o.pass_threshold;
  j["pass"] = result.pass;
  j["rows"] = std::move(rows);
  j["power_curves"] = std::move(curves);
  j["wall_seconds"] = number(result.wall_seconds);
  return j;
}

void print_tile_calibration(const TileCalibrationResult& result, std::ostream& out) {
  const TileCalibrationOptions& o = result.options;
  out << fmt::format(
      "Tile calibration: seeds {}..{}, {} replicate images x {} spp; each comparison decided "
      "alone at alpha = {} (rejected when some tile p <= alpha / T); a row passes when its "
      "one-sided binomial p and its fixed tile's KS p are >= {}\n",
      o.first_seed, o.first_seed + o.seeds - 1, o.replicates, o.samples, o.test_alpha,
      o.pass_threshold);
  out << fmt::format("{:<16} {:<44} {:>4} {:>12} {:>22} {:>8} {:>9} {:>9} {:>9}  {}\n", "scene",
                     "comparison", "T", "false alarms", "rate [95% Wilson]", "expected", "binom p",
                     "upper p", "tile KS p", "pass");
  for (const TileSizeRow& row : result.rows) {
    const std::string name =
        fmt::format("{} vs {}{}", row.estimator_a, row.estimator_b, row.biased ? " (biased)" : "");
    out << fmt::format(
        "{:<16} {:<44} {:>4} {:>12} {:>22} {:>8.1f} {:>9.3g} {:>9.3g} {:>9.3g}  {}\n",
        fmt::format("{} {}x{}", row.scene, row.width, row.height), name, row.tests,
        fmt::format("{} / {}", row.false_alarms, row.seeds),
        fmt::format("{:.3f} [{:.3f}, {:.3f}]", row.false_alarm_rate, row.wilson_low,
                    row.wilson_high),
        row.expected_false_alarms, row.binomial_p_value, row.binomial_upper_p_value,
        row.fixed_tile_ks.p_value, row.pass ? "yes" : "NO");
  }
  out << fmt::format("tile calibration: {}\n", result.pass ? "pass" : "FAIL");
  for (const TilePowerCurve& c : result.power) {
    const InjectedTile& top = c.injected_tiles.front();
    const std::string where =
        c.tile_rule == "brightest"
            ? fmt::format(
                  "brightest tile (the self-check's rule; tile {},{} channel {} in {} "
                  "of {} seeds)",
                  top.tile_x, top.tile_y, top.channel, top.seeds, c.seeds)
            : fmt::format("centre tile {},{} channel {} (fixed)", top.tile_x, top.tile_y,
                          top.channel);
    out << fmt::format(
        "\nPower on {} ({}x{}), bias into {}'s {} against {}: T = {}, tile threshold alpha/T = "
        "{:.3g}, median Welch dof {:.1f}, median MDB {:.4g} ({:.2f}% of the tile mean), RMS "
        "stderr {:.4g}, mean statistic before the bias {:.3f}\n",
        c.scene, c.width, c.height, c.estimator_a, where, c.estimator_b, c.tests, c.share,
        c.median_dof, c.median_mdb, 100.0 * c.median_relative_mdb, c.rms_stderr, c.mean_statistic);
    out << fmt::format("{:>5} | {:>9} {:>22} {:>22} {:>9} | {:>10} {:>9} {:>22} {:>22} {:>9}\n",
                       "k", "k x MDB", "detected [Wilson]", "tile alone", "predicted", "fixed bias",
                       "detected", "rate [Wilson]", "tile alone", "predicted");
    const auto interval = [](double rate, double low, double high) {
      return fmt::format("{:.3f} [{:.3f}, {:.3f}]", rate, low, high);
    };
    for (const TilePowerPoint& p : c.points) {
      out << fmt::format(
          "{:>5.2f} | {:>9} {:>22} {:>22} {:>9.3f} | {:>10.4g} {:>9} {:>22} {:>22} {:>9.3f}\n",
          p.multiplier, fmt::format("{}/{}", p.detections, c.seeds),
          interval(p.detection_rate, p.wilson_low, p.wilson_high),
          interval(p.tile_detection_rate, p.tile_wilson_low, p.tile_wilson_high), p.predicted_power,
          p.fixed_bias, fmt::format("{}/{}", p.fixed_detections, c.seeds),
          interval(p.fixed_detection_rate, p.fixed_wilson_low, p.fixed_wilson_high),
          interval(p.fixed_tile_detection_rate, p.fixed_tile_wilson_low, p.fixed_tile_wilson_high),
          p.fixed_predicted_power);
    }
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
