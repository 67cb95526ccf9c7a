#include "harness/verify/scene_calibration.h"

#include <fmt/format.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>

#include "base/errors.h"
#include "estimators/scene/scene_estimator.h"
#include "harness/plan/plan.h"
#include "harness/run/runner.h"
#include "harness/verify/block_checks.h"
#include "harness/verify/block_pyramid.h"

namespace pcbench {
namespace {

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

}  // namespace pcbench
