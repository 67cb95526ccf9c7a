// The table of estimators: the one place an estimator is made known to pcbench (no static
// self-registration, which silently loses entries at link time). Each estimator's file defines
// one function returning its whole row, an EstimatorEntry (both forms, parameters, and for a
// negative control its declared workload); estimators/registry.cpp lists those functions, one
// line each.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/params.h"
#include "estimators/estimator.h"
#include "estimators/scene/scene_form.h"

namespace pcbench {

// Where a negative control is known to be biased: the integrand (with parameters) and the budget
// at which the verifier must flag it. `pcbench verify -e CONTROL` runs this when no integrand is
// named.
struct DeclaredWorkload {
  std::string integrand = {};
  ParamText integrand_params = {};
  std::uint64_t samples = 0;
  std::uint32_t replicates = 0;
  // Honest estimators run beside the control. A scene control is caught by the tile tests
  // against an honest run (a scene without an exact image has no reference to test one run
  // against), so `verify -e CONTROL` runs these too; the control is then flagged only if a
  // comparison with them says so.
  std::vector<std::string> partners = {};
};

// A parameter set of an estimator, over its defaults, with a name to show for it.
struct NamedParams {
  std::string name;
  ParamText params;
};

// What tests/scene_mis_test.cpp runs of a scene estimator besides its defaults. Every scene
// estimator's MIS weights are checked at its defaults on random paths of three scenes, and every
// honest one renders an 8×8 furnace to its exact radiance, alike with 1 and 2 threads.
struct SceneTests {
  // Further parameter sets whose MIS weights are checked (pcbpt's ablations).
  std::vector<NamedParams> weights = {};
  // The furnace renders of an honest estimator, instead of one at its defaults (a smaller pool
  // for 8×8 pixels; ablations). A negative control renders none.
  std::vector<NamedParams> renders = {};
};

struct EstimatorEntry {
  std::string name;
  std::string description;
  bool biased = false;  // a negative control: the verifier must flag it
  // Other names find_estimator accepts for this row (plain's `bdpt`). A run asked for by one is
  // the run asked for by `name`: plans, reports and run ids use the row, and so `name`.
  std::vector<std::string> aliases = {};
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<Estimator>(const ResolvedParams&)> make;
  std::optional<DeclaredWorkload> declared = {};  // set for every negative control
  // Scenes (estimators/scene/scene_form.h): the parameters the estimator reads on a scene
  // and the factory of its SceneEstimator (its SceneForm). Unset: the estimator works on
  // analytic integrands only; `make` unset: on scenes only.
  std::vector<ParamSpec> scene_params = {};
  MakeSceneEstimator make_render = {};
  // Named configurations of its scene form, as parameters over its defaults (pcbpt's published
  // and legacy tile designs), defined once in its file; `pcbench list` shows them.
  std::vector<NamedParams> scene_configurations = {};
  SceneTests scene_tests = {};  // what the scene tests run of it, besides its defaults

  bool renders_scenes() const { return static_cast<bool>(make_render); }
  bool samples_analytic() const { return static_cast<bool>(make); }
};

// A list of entry functions written once and used twice (an X-macro), as estimators/registry.cpp
// lists the estimators:
//     #define MY_ESTIMATORS(ESTIMATOR) ESTIMATOR(pt_entry) ESTIMATOR(lt_entry)
//     MY_ESTIMATORS(PCBENCH_DECLARE_ENTRY)         // EstimatorEntry pt_entry(); … lt_entry();
//     rows = {MY_ESTIMATORS(PCBENCH_CALL_ENTRY)};  // rows = {pt_entry(), lt_entry(),};
#define PCBENCH_DECLARE_ENTRY(function) EstimatorEntry function();
#define PCBENCH_CALL_ENTRY(function) function(),

// Estimators of analytic integrands (most of which render scenes too).
const std::vector<EstimatorEntry>& estimator_registry();
// Estimators of scenes only (path tracing, light tracing, the scene negative controls).
const std::vector<EstimatorEntry>& scene_estimator_registry();

// Adds a row to the scene-only table, for a binary that brings estimators of its own
// (examples/main.cpp). Call it before anything looks an estimator up: rows may move.
void register_scene_estimator(EstimatorEntry entry);

// The row named or aliased `name`; throws InputError naming the valid estimators.
const EstimatorEntry& find_estimator(const std::string& name);

// The scene form of estimator `name` with `params` (defaults for the rest), as a run makes it:
// for tests and benchmarks. Throws InputError for a bad name or value, or an estimator that
// does not render scenes.
std::shared_ptr<const scene::SceneEstimator> make_scene_estimator(const std::string& name,
                                                                  const ParamText& params = {});

}  // namespace pcbench
