#include "harness/commands/tile_calibration.h"

#include <fmt/format.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <set>
#include <stdexcept>

#include "base/errors.h"
#include "estimators/scene/scene_estimator.h"
#include "harness/commands/calibration.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/session/report.h"
#include "harness/verify/block_checks.h"
#include "harness/verify/block_pyramid.h"
#include "harness/verify/pyramid_calibration.h"

namespace pcbench {
namespace {

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

// A power curve: the comparison, the scale whose block takes the bias, the rule that chooses it.
struct CurveSpec {
  std::size_t row = 0;
  std::size_t scale = 0;
  InjectionRule rule = InjectionRule::kBrightest;
};

struct SeedOutcome {
  std::vector<SizeSeed> rows;        // per comparison
  std::vector<InjectionSeed> power;  // per curve
};

// One seed's replicate images: per scene, per estimator (in the order of options.estimators).
using SeedImages = std::vector<std::vector<std::vector<Image>>>;

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
          "{}: '{}' is not a scene (the block pyramid is calibrated on scenes; `pcbench calibrate` "
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
  if (options.paired) pair_scene_streams(plans);
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

// The scales of a scene's pyramid.
std::size_t scale_count(const ScenePlans& scene) {
  const scene::SceneDescription& d = scene.integrand->scene().description();
  return pyramid_block_sizes(d.width, d.height, PyramidOptions{}.tile).size();
}

// The power curves: each compared scene's first pair; the brightest block at each scale (the
// session's self-check), then the fixed centre block at each scale (no selection: the MDB's own
// promise).
std::vector<CurveSpec> curve_specs(const TileCalibrationOptions& options,
                                   const std::vector<ComparisonSpec>& specs,
                                   const std::vector<ScenePlans>& scenes) {
  std::vector<CurveSpec> curves;
  if (options.bias_multipliers.empty()) return curves;
  for (std::size_t r = 0; r < specs.size(); ++r) {
    if (specs[r].b < 0 || (r > 0 && specs[r - 1].scene == specs[r].scene)) continue;
    const std::size_t scales = scale_count(scenes[specs[r].scene]);
    for (const InjectionRule rule : {InjectionRule::kBrightest, InjectionRule::kCentre}) {
      for (std::size_t s = 0; s < scales; ++s) curves.push_back({r, s, rule});
    }
  }
  return curves;
}

// The comparison's pyramid, decided alone at alpha, with `a` as its first side.
PyramidResult compare(const ComparisonSpec& spec, const std::vector<Image>& a,
                      const SeedImages& images, const std::vector<ScenePlans>& scenes,
                      double alpha) {
  const ScenePlans& scene = scenes[spec.scene];
  if (spec.b < 0) return test_blocks_against_exact(a, *scene.exact, alpha);
  const auto b = static_cast<std::size_t>(spec.b);
  return compare_blocks(a, images[spec.scene][b], alpha,
                        {.paired = share_streams(*scene.runs[spec.a], *scene.runs[b])});
}

// One seed: every run, every comparison, every curve's injections.
SeedOutcome run_seed(std::uint64_t seed, const TileCalibrationOptions& options,
                     const std::vector<ScenePlans>& scenes,
                     const std::vector<ComparisonSpec>& specs,
                     const std::vector<CurveSpec>& curves) {
  SeedImages images(scenes.size());
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    for (const RunPlan* plan : scenes[s].runs) {
      images[s].push_back(render(*plan, seed, options.interrupted));
    }
  }
  SeedOutcome out;
  std::vector<PyramidResult> tests;
  for (const ComparisonSpec& spec : specs) {
    const std::vector<Image>& a = images[spec.scene][spec.a];
    tests.push_back(compare(spec, a, images, scenes, options.test_alpha));
    out.rows.push_back(size_seed(tests.back(), a.front().width, a.front().height));
  }
  for (const CurveSpec& curve : curves) {
    const ComparisonSpec& spec = specs[curve.row];
    const Retest retest = [&](const std::vector<Image>& biased) {
      return compare(spec, biased, images, scenes, options.test_alpha);
    };
    out.power.push_back(inject_own_mdb(tests[curve.row], curve.scale, curve.rule,
                                       images[spec.scene][spec.a], retest, options.bias_multipliers,
                                       options.test_alpha));
  }
  return out;
}

// The scene, the image size, the estimators and the runs of a row or a curve.
template <class Entry>
void identify(Entry& entry, const ComparisonSpec& spec, const std::vector<ScenePlans>& scenes,
              const TileCalibrationOptions& options) {
  const ScenePlans& scene = scenes[spec.scene];
  const scene::SceneDescription& d = scene.integrand->scene().description();
  entry.scene = options.scenes[spec.scene];
  entry.width = d.width;
  entry.height = d.height;
  const RunPlan& a = *scene.runs[spec.a];
  entry.estimator_a = a.estimator->name;
  entry.run_a = a.id;
  if (spec.b < 0) {
    entry.estimator_b = entry.run_b = "exact";
  } else {
    const RunPlan& b = *scene.runs[static_cast<std::size_t>(spec.b)];
    entry.estimator_b = b.estimator->name;
    entry.run_b = b.id;
  }
}

TileSizeRow size_row(const ComparisonSpec& spec, std::size_t r,
                     const std::vector<ScenePlans>& scenes,
                     const std::vector<SeedOutcome>& outcomes,
                     const TileCalibrationOptions& options) {
  std::vector<SizeSeed> seeds;
  for (const SeedOutcome& o : outcomes) seeds.push_back(o.rows[r]);
  TileSizeRow row;
  static_cast<PyramidSizeRow&>(row) =
      pyramid_size_row(seeds, options.test_alpha, options.pass_threshold);
  identify(row, spec, scenes, options);
  const ScenePlans& scene = scenes[spec.scene];
  row.biased = scene.runs[spec.a]->estimator->biased ||
               (spec.b >= 0 && scene.runs[static_cast<std::size_t>(spec.b)]->estimator->biased);
  return row;
}

TilePowerCurve power_curve(const CurveSpec& spec, std::size_t c,
                           const std::vector<ComparisonSpec>& specs,
                           const std::vector<ScenePlans>& scenes,
                           const std::vector<SeedOutcome>& outcomes,
                           const TileCalibrationOptions& options) {
  std::vector<InjectionSeed> seeds;
  for (const SeedOutcome& o : outcomes) seeds.push_back(o.power[c]);
  TilePowerCurve curve;
  static_cast<ScalePowerCurve&>(curve) =
      scale_power_curve(seeds, spec.rule, spec.scale, options.bias_multipliers);
  identify(curve, specs[spec.row], scenes, options);
  return curve;
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
  const std::vector<CurveSpec> curves = curve_specs(options, specs, scenes);
  std::vector<SeedOutcome> outcomes(options.seeds);
  tbb::parallel_for(std::uint32_t{0}, options.seeds, [&](std::uint32_t i) {
    outcomes[i] = run_seed(options.first_seed + i, options, scenes, specs, curves);
  });
  for (std::size_t r = 0; r < specs.size(); ++r) {
    result.rows.push_back(size_row(specs[r], r, scenes, outcomes, options));
  }
  result.pass = std::all_of(result.rows.begin(), result.rows.end(),
                            [](const TileSizeRow& row) { return row.pass; });
  for (std::size_t c = 0; c < curves.size(); ++c) {
    result.power.push_back(power_curve(curves[c], c, specs, scenes, outcomes, options));
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

void add_false_alarms(Json& j, const FalseAlarms& f) {
  j["seeds"] = f.seeds;
  j["false_alarms"] = f.false_alarms;
  j["false_alarm_rate"] = number(f.false_alarm_rate);
  j["wilson_low"] = number(f.wilson_low);
  j["wilson_high"] = number(f.wilson_high);
  j["binomial_p_value"] = number(f.binomial_p_value);
  j["binomial_upper_p_value"] = number(f.binomial_upper_p_value);
}

Json scale_row_json(const ScaleSizeRow& s) {
  Json j = Json::object();
  j["block"] = s.block;
  j["tests"] = s.tests;
  add_false_alarms(j, s);
  j["expected_share"] = number(s.expected_share);
  j["expected_false_alarms"] = number(s.expected_false_alarms);
  j["centre_block"] = {{"x", s.centre_x},
                       {"y", s.centre_y},
                       {"channel", s.centre_channel},
                       {"ks_statistic", number(s.centre_ks.statistic)},
                       {"ks_p_value", number(s.centre_ks.p_value)},
                       {"p_values", numbers(s.centre_p_values)}};
  j["median_bright_relative_mdb"] = number(s.median_bright_relative_mdb);
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
  j["expected_false_alarms"] = number(row.expected_false_alarms);
  j["pass"] = row.pass;
  Json scales = Json::array();
  for (const ScaleSizeRow& s : row.scales) scales.push_back(scale_row_json(s));
  j["scales"] = std::move(scales);
  j["min_p_adjusted"] = numbers(row.min_p_adjusted);
  return j;
}

Json point_json(const BlockPowerPoint& p) {
  return Json{{"multiplier", number(p.multiplier)},
              {"detections", p.detections},
              {"detection_rate", number(p.detection_rate)},
              {"wilson_low", number(p.wilson_low)},
              {"wilson_high", number(p.wilson_high)},
              {"block_detections", p.block_detections},
              {"block_detection_rate", number(p.block_detection_rate)},
              {"block_wilson_low", number(p.block_wilson_low)},
              {"block_wilson_high", number(p.block_wilson_high)},
              {"predicted_power", number(p.predicted_power)}};
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
              {"share", number(c.share)},
              {"median_mdb", number(c.median_mdb)},
              {"median_relative_mdb", number(c.median_relative_mdb)},
              {"rms_stderr", number(c.rms_stderr)},
              {"median_dof", number(c.median_dof)},
              {"mean_statistic", number(c.mean_statistic)},
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
  j["wall_seconds"] = number(result.wall_seconds);
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
