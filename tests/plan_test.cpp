#include "harness/plan/plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "base/errors.h"

namespace pcbench {
namespace {

using Values = std::map<std::string, std::vector<std::string>>;

GridRequest grid(std::vector<std::string> estimators, std::vector<std::string> integrands,
                 Values params = {}, std::string where = "test") {
  GridRequest g;
  g.estimators = std::move(estimators);
  g.integrands = std::move(integrands);
  g.params = std::move(params);
  g.where = std::move(where);
  return g;
}

GridRequest row(const std::string& integrand, Values params = {}, std::string where = "test") {
  return grid({"plain"}, {integrand}, std::move(params), std::move(where));
}

// The InputError message of plan_runs(grids, budget), or "" when it does not throw.
std::string plan_error(const std::vector<GridRequest>& grids, const BudgetDefaults& budget = {}) {
  try {
    plan_runs(grids, budget);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string single_id(const GridRequest& request, const BudgetDefaults& budget = {}) {
  const std::vector<RunPlan> plans = plan_runs({request}, budget);
  EXPECT_EQ(plans.size(), 1u);
  return plans.empty() ? std::string() : plans[0].id;
}

// ---------------------------------------------------------------------------------------------
// Grid expansion

TEST(PlanGrid, ExpandsToTheProductOfItsLists) {
  const std::vector<RunPlan> plans = plan_runs(
      {grid({"plain"}, {"genz-gaussian", "genz-oscillatory"}, {{"sharpness", {"1", "2", "3"}}})},
      {});
  ASSERT_EQ(plans.size(), 6u);
  std::set<std::string> ids;
  std::multiset<std::pair<std::string, double>> combinations;
  for (const RunPlan& plan : plans) {
    ids.insert(plan.id);
    combinations.insert({plan.integrand->name, plan.integrand_params.real("sharpness")});
    EXPECT_EQ(plan.estimator->name, "plain");
    EXPECT_NE(plan.made_estimator, nullptr);
    EXPECT_NE(plan.made_integrand, nullptr);
  }
  EXPECT_EQ(ids.size(), 6u);
  const std::multiset<std::pair<std::string, double>> expected = {
      {"genz-gaussian", 1.0},    {"genz-gaussian", 2.0},    {"genz-gaussian", 3.0},
      {"genz-oscillatory", 1.0}, {"genz-oscillatory", 2.0}, {"genz-oscillatory", 3.0}};
  EXPECT_EQ(combinations, expected);
}

TEST(PlanGrid, ProductOverTwoKeys) {
  const std::vector<RunPlan> plans = plan_runs(
      {row("genz-gaussian", {{"sharpness", {"1", "2"}}, {"light_dims", {"1", "2", "3"}}})}, {});
  EXPECT_EQ(plans.size(), 6u);
}

TEST(PlanGrid, KeyARowDoesNotReadIsDroppedForThatRow) {
  const std::vector<RunPlan> plans = plan_runs(
      {grid({"plain"}, {"genz-gaussian", "expr"}, {{"sharpness", {"1", "2"}}, {"f", {"x0*y0"}}})},
      {});
  ASSERT_EQ(plans.size(), 3u);  // two genz-gaussian rows, one expr row
  int gaussian = 0, expression = 0;
  for (const RunPlan& plan : plans) {
    if (plan.integrand->name == "expr") {
      ++expression;
      EXPECT_FALSE(plan.integrand_params.has("sharpness"));
      EXPECT_EQ(plan.integrand_params.text("f"), "x0*y0");
    } else {
      ++gaussian;
      EXPECT_FALSE(plan.integrand_params.has("f"));
    }
  }
  EXPECT_EQ(gaussian, 2);
  EXPECT_EQ(expression, 1);
}

TEST(PlanGrid, KeyReadByNoRowIsAnErrorListingWhatEachReads) {
  const std::string message = plan_error({grid({"plain"}, {"genz-gaussian", "genz-oscillatory"},
                                               {{"sharpnes", {"1"}}}, "suite.json: /grid/0")});
  EXPECT_TRUE(contains(message, "suite.json: /grid/0")) << message;
  EXPECT_TRUE(contains(message, "'sharpnes'")) << message;
  EXPECT_TRUE(contains(message, "estimator 'plain' reads: none")) << message;
  EXPECT_TRUE(contains(
      message, "integrand 'genz-gaussian' reads: light_dims, camera_dims, sharpness, center"))
      << message;
  EXPECT_TRUE(contains(message, "integrand 'genz-oscillatory' reads:")) << message;
}

TEST(PlanGrid, ReadKeyWithoutValuesIsRejected) {
  const std::string message = plan_error({row("genz-gaussian", {{"sharpness", {}}})});
  EXPECT_TRUE(contains(message, "'sharpness'")) << message;
  EXPECT_TRUE(contains(message, "no values")) << message;
}

TEST(PlanGrid, EmptyEstimatorOrIntegrandListIsRejected) {
  EXPECT_TRUE(contains(plan_error({grid({}, {"genz-gaussian"})}), "no estimator"));
  EXPECT_TRUE(contains(plan_error({grid({"plain"}, {})}), "no integrand"));
}

// ---------------------------------------------------------------------------------------------
// Collapsing identical rows

TEST(PlanCollapse, IdenticalRowsCollapseKeepingTheFirst) {
  const std::vector<RunPlan> plans = plan_runs(
      {row("genz-gaussian", {{"sharpness", {"2"}}}, "first"), row("genz-oscillatory", {}, "other"),
       row("genz-gaussian", {{"sharpness", {"2"}}}, "second")},
      {});
  ASSERT_EQ(plans.size(), 2u);
  EXPECT_EQ(plans[0].where, "first");
  EXPECT_EQ(plans[1].where, "other");
}

TEST(PlanCollapse, EqualValuesSpelledDifferentlyInOneGridCollapse) {
  const std::vector<RunPlan> plans =
      plan_runs({row("genz-gaussian", {{"sharpness", {"4", "4.0", "4e0", "5"}}})}, {});
  ASSERT_EQ(plans.size(), 2u);
  EXPECT_EQ(plans[0].integrand_params.real("sharpness"), 4.0);
  EXPECT_EQ(plans[1].integrand_params.real("sharpness"), 5.0);
}

// A suite of eight lists of ten values (fuzz/regressions/suite/grid-explosion.json) asked for
// 10^8 runs: planning timed out in the suite fuzz target and would have run out of memory.
TEST(PlanGrid, AGridOfTooManyRunsIsRejectedBeforeExpanding) {
  Values params;
  for (const char* key : {"M", "K", "cache_cells", "light_dims", "camera_dims", "sharpness"}) {
    for (int v = 1; v <= 10; ++v) params[key].push_back(std::to_string(v));
  }
  const std::string message = plan_error({grid({"pcbpt"}, {"genz-gaussian"}, params)});
  EXPECT_TRUE(contains(message, "test: more than 100000 runs in all")) << message;
}

TEST(PlanCollapse, RowsThatDifferOnlyInAKeyTheyDoNotReadCollapse) {
  // `f` is dropped for genz-gaussian rows; the two remaining rows are the same run.
  const std::vector<RunPlan> plans =
      plan_runs({grid({"plain"}, {"genz-gaussian", "expr"}, {{"f", {"x0", "y0"}}})}, {});
  ASSERT_EQ(plans.size(), 3u);  // genz-gaussian once, expr twice
  EXPECT_EQ(std::count_if(plans.begin(), plans.end(),
                          [](const RunPlan& p) { return p.integrand->name == "genz-gaussian"; }),
            1);
}

// ---------------------------------------------------------------------------------------------
// Run ids

TEST(PlanId, IsSixteenHexDigitsOfTheHash) {
  const std::vector<RunPlan> plans =
      plan_runs({row("genz-gaussian", {{"sharpness", {"1", "2", "3"}}})}, {});
  for (const RunPlan& plan : plans) {
    // std::regex would trip a false -Wmaybe-uninitialized of GCC 12 under ASan.
    EXPECT_EQ(plan.id.size(), 16u) << plan.id;
    EXPECT_EQ(plan.id.find_first_not_of("0123456789abcdef"), std::string::npos) << plan.id;
    EXPECT_EQ(std::stoull(plan.id, nullptr, 16), plan.id_hash) << plan.id;
  }
}

TEST(PlanId, EqualsRunIdHashOfTheEffectiveParameters) {
  BudgetDefaults budget;
  budget.samples = 1234;
  budget.replicates = 5;
  const std::vector<RunPlan> plans = plan_runs({row("genz-gaussian")}, budget);
  ASSERT_EQ(plans.size(), 1u);
  EXPECT_EQ(plans[0].id_hash,
            run_id_hash(
                "plain", "genz-gaussian",
                {{"camera_dims", "1"}, {"center", "0.5"}, {"light_dims", "1"}, {"sharpness", "4"}},
                1234, 5));
}

TEST(PlanId, DependsOnIntegrandParamsSamplesAndReplicates) {
  BudgetDefaults budget;
  budget.samples = 1000;
  budget.replicates = 8;
  std::set<std::string> ids;
  ids.insert(single_id(row("genz-gaussian"), budget));
  ids.insert(single_id(row("genz-oscillatory"), budget));
  ids.insert(single_id(row("genz-gaussian", {{"sharpness", {"5"}}}), budget));
  ids.insert(single_id(row("genz-gaussian", {{"center", {"0.25"}}}), budget));
  ids.insert(single_id(row("genz-gaussian", {{"light_dims", {"2"}}}), budget));
  GridRequest more_samples = row("genz-gaussian");
  more_samples.samples = 1001;
  ids.insert(single_id(more_samples, budget));
  GridRequest more_replicates = row("genz-gaussian");
  more_replicates.replicates = 9;
  ids.insert(single_id(more_replicates, budget));
  EXPECT_EQ(ids.size(), 7u);
}

TEST(PlanId, HashDependsOnEveryComponent) {
  const std::map<std::string, std::string> params = {{"M", "4"}};
  const std::uint64_t base = run_id_hash("a", "b", params, 100, 8);
  EXPECT_EQ(run_id_hash("a", "b", params, 100, 8), base);
  EXPECT_NE(run_id_hash("c", "b", params, 100, 8), base);
  EXPECT_NE(run_id_hash("a", "c", params, 100, 8), base);
  EXPECT_NE(run_id_hash("a", "b", {{"M", "5"}}, 100, 8), base);
  EXPECT_NE(run_id_hash("a", "b", {{"K", "4"}}, 100, 8), base);
  EXPECT_NE(run_id_hash("a", "b", {}, 100, 8), base);
  EXPECT_NE(run_id_hash("a", "b", params, 101, 8), base);
  EXPECT_NE(run_id_hash("a", "b", params, 100, 9), base);
  // Field boundaries matter: ("ab", "c") is not ("a", "bc").
  EXPECT_NE(run_id_hash("ab", "c", {}, 100, 8), run_id_hash("a", "bc", {}, 100, 8));
  EXPECT_NE(run_id_hash("a", "b", {{"M", "14"}}, 100, 8),
            run_id_hash("a", "b", {{"M1", "4"}}, 100, 8));
}

// A pilot of 2 replicates × N samples is not the run of 2 replicates × N: it must not take (and
// so correlate with) the numbers of the run whose sample count it chooses.
TEST(PlanId, APilotNeverHasTheIdOfARun) {
  GridRequest two = row("genz-gaussian");
  two.samples = 8192;
  two.replicates = 2;
  const RunPlan run = plan_runs({two}, {}).at(0);
  RunPlan pilot = run;
  pilot.pilot = true;
  assign_id(pilot);
  EXPECT_NE(pilot.id_hash, run.id_hash);
  EXPECT_NE(pilot.id, run.id);
}

// Paired streams: the scene runs of two estimators share their streams (and so their camera
// paths, replicate by replicate) while their ids stay apart, and differ from the unpaired ids;
// another resolution, budget or an analytic run does not pair.
TEST(PlanId, PairedSceneRunsShareStreamsButNotIds) {
  std::vector<RunPlan> plans = plan_runs(
      {grid({"pt", "plain"}, {"furnace"}, {{"resolution", {"8", "16"}}}), row("genz-gaussian")},
      {});
  ASSERT_EQ(plans.size(), 5u);
  const std::vector<RunPlan> own = plans;
  for (const RunPlan& p : own) EXPECT_EQ(p.stream_hash, p.id_hash);
  pair_scene_streams(plans);
  const auto find = [&](const std::string& estimator, const std::string& resolution) {
    for (const RunPlan& p : plans) {
      if (p.estimator->name == estimator && p.integrand->name == "furnace" &&
          to_text(p.integrand_params.values().at("resolution")) == resolution) {
        return p;
      }
    }
    ADD_FAILURE() << estimator << " at " << resolution;
    return RunPlan{};
  };
  const RunPlan pt8 = find("pt", "8"), plain8 = find("plain", "8"), pt16 = find("pt", "16");
  EXPECT_TRUE(share_streams(pt8, plain8));
  EXPECT_NE(pt8.id, plain8.id);
  EXPECT_FALSE(share_streams(pt8, pt16));
  for (std::size_t i = 0; i < plans.size(); ++i) {
    EXPECT_EQ(plans[i].paired_streams, plans[i].render != nullptr);
    EXPECT_EQ(plans[i].id == own[i].id, plans[i].render == nullptr) << plans[i].id;
  }
  EXPECT_FALSE(share_streams(pt8, own[0]));
  // Another budget: other streams.
  EXPECT_FALSE(share_streams(pt8, with_samples(plain8, plain8.samples * 2)));
  EXPECT_TRUE(share_streams(with_samples(pt8, 64), with_samples(plain8, 64)));
}

TEST(PlanId, DoesNotDependOnRowOrder) {
  const GridRequest a = row("genz-gaussian", {{"sharpness", {"2"}}});
  const GridRequest b = row("genz-oscillatory", {{"center", {"0.1"}}});
  const std::vector<RunPlan> ab = plan_runs({a, b}, {});
  const std::vector<RunPlan> ba = plan_runs({b, a}, {});
  ASSERT_EQ(ab.size(), 2u);
  ASSERT_EQ(ba.size(), 2u);
  EXPECT_EQ(ab[0].id, ba[1].id);
  EXPECT_EQ(ab[1].id, ba[0].id);
  EXPECT_NE(ab[0].id, ab[1].id);
}

TEST(PlanId, DoesNotDependOnTheOrderOfGridLists) {
  const std::vector<RunPlan> forward = plan_runs(
      {grid({"plain"}, {"genz-gaussian", "genz-oscillatory"}, {{"sharpness", {"1", "2"}}})}, {});
  const std::vector<RunPlan> backward = plan_runs(
      {grid({"plain"}, {"genz-oscillatory", "genz-gaussian"}, {{"sharpness", {"2", "1"}}})}, {});
  std::set<std::string> forward_ids, backward_ids;
  for (const RunPlan& p : forward) forward_ids.insert(p.id);
  for (const RunPlan& p : backward) backward_ids.insert(p.id);
  EXPECT_EQ(forward_ids.size(), 4u);
  EXPECT_EQ(forward_ids, backward_ids);
}

TEST(PlanId, ExplicitDefaultsGiveTheSameIdAsImpliedOnes) {
  const std::string implied = single_id(row("genz-gaussian"));
  EXPECT_EQ(single_id(row("genz-gaussian", {{"sharpness", {"4"}}})), implied);
  EXPECT_EQ(single_id(row("genz-gaussian", {{"sharpness", {"4.0"}}})), implied);
  EXPECT_EQ(single_id(row("genz-gaussian", {{"center", {"0.5"}},
                                            {"light_dims", {"1"}},
                                            {"camera_dims", {"1"}},
                                            {"sharpness", {"4"}}})),
            implied);
  EXPECT_NE(single_id(row("genz-gaussian", {{"sharpness", {"4.5"}}})), implied);
}

TEST(PlanId, ExplicitBudgetEqualToTheDefaultGivesTheSameId) {
  BudgetDefaults budget;
  budget.samples = 2000;
  budget.replicates = 6;
  const std::string implied = single_id(row("genz-gaussian"), budget);
  GridRequest explicit_row = row("genz-gaussian");
  explicit_row.samples = 2000;
  explicit_row.replicates = 6;
  EXPECT_EQ(single_id(explicit_row, budget), implied);
}

TEST(PlanId, DoesNotDependOnWhereOrExpect) {
  GridRequest a = row("genz-gaussian", {}, "a.json: /runs/0");
  GridRequest b = row("genz-gaussian", {}, "b.json: /grid/3");
  b.expect = "biased";
  EXPECT_EQ(single_id(a), single_id(b));
}

// ---------------------------------------------------------------------------------------------
// Budgets

TEST(PlanBudget, RowValuesOverrideDefaultsAndForcedValuesOverrideRows) {
  GridRequest with_budget = row("genz-gaussian");
  with_budget.samples = 500;
  with_budget.replicates = 4;
  BudgetDefaults budget;
  budget.samples = 1000;
  budget.replicates = 8;

  const std::vector<RunPlan> plain_rows = plan_runs({row("genz-gaussian"), with_budget}, budget);
  ASSERT_EQ(plain_rows.size(), 2u);
  EXPECT_EQ(plain_rows[0].samples, 1000u);
  EXPECT_EQ(plain_rows[0].replicates, 8u);
  EXPECT_EQ(plain_rows[1].samples, 500u);
  EXPECT_EQ(plain_rows[1].replicates, 4u);

  budget.forced_samples = 77;
  budget.forced_replicates = 3;
  const std::vector<RunPlan> forced = plan_runs({with_budget}, budget);
  ASSERT_EQ(forced.size(), 1u);
  EXPECT_EQ(forced[0].samples, 77u);
  EXPECT_EQ(forced[0].replicates, 3u);
  GridRequest expected_row = row("genz-gaussian");
  expected_row.samples = 77;
  expected_row.replicates = 3;
  EXPECT_EQ(forced[0].id, single_id(expected_row));
}

TEST(PlanBudget, DefaultsAreTheInterfaceDefaults) {
  const std::vector<RunPlan> plans = plan_runs({row("genz-gaussian")}, {});
  ASSERT_EQ(plans.size(), 1u);
  EXPECT_EQ(plans[0].samples, 100000u);
  EXPECT_EQ(plans[0].replicates, 32u);
}

// The scene default (16 spp) applies only when nothing sets samples: an explicit 100000 (the
// analytic default) on a scene is 100000 spp, from the command line or a suite's defaults.
TEST(PlanBudget, ASceneTakesItsDefaultOnlyWhenSamplesAreUnset) {
  const GridRequest scene = grid({"pt"}, {"furnace"}, {{"resolution", {"8"}}});
  EXPECT_EQ(plan_runs({scene}, {}).at(0).samples, kDefaultScenePixelSamples);
  BudgetDefaults forced;
  forced.forced_samples = kDefaultSamples;  // pcbench run -e pt -i furnace -n 100000
  EXPECT_EQ(plan_runs({scene}, forced).at(0).samples, 100000u);
  BudgetDefaults suite_default;
  suite_default.samples = kDefaultSamples;  // "defaults": {"samples": 100000}
  EXPECT_EQ(plan_runs({scene}, suite_default).at(0).samples, 100000u);
  GridRequest row_budget = scene;
  row_budget.samples = kDefaultSamples;
  EXPECT_EQ(plan_runs({row_budget}, {}).at(0).samples, 100000u);
  // Both kinds in one grid: each takes its own default.
  const std::vector<RunPlan> mixed =
      plan_runs({grid({"plain"}, {"genz-gaussian", "furnace"}, {{"resolution", {"8"}}})}, {});
  ASSERT_EQ(mixed.size(), 2u);
  EXPECT_EQ(mixed[0].samples, kDefaultSamples);
  EXPECT_EQ(mixed[1].samples, kDefaultScenePixelSamples);
}

TEST(PlanBudget, ZeroSamplesAreRejected) {
  GridRequest zero = row("genz-gaussian");
  zero.samples = 0;
  EXPECT_TRUE(contains(plan_error({zero}), "samples = 0")) << plan_error({zero});
  BudgetDefaults budget;
  budget.samples = 0;
  EXPECT_TRUE(contains(plan_error({row("genz-gaussian")}, budget), "samples = 0"));
  BudgetDefaults forced;
  forced.forced_samples = 0;
  EXPECT_TRUE(contains(plan_error({row("genz-gaussian")}, forced), "samples = 0"));
}

TEST(PlanBudget, SamplesAboveTheCounterLimitAreRejected) {
  GridRequest huge = row("genz-gaussian");
  huge.samples = kMaxSamples + 1;
  EXPECT_TRUE(contains(plan_error({huge}), "out of range"));
}

// A scene takes an equal-time budget as an analytic integrand does (its pilot chooses the
// samples per pixel), within the same range.
TEST(PlanBudget, AScenePlansSecondsWithinTheirRange) {
  GridRequest scene = grid({"pt"}, {"furnace"}, {{"resolution", {"8"}}});
  scene.seconds = 0.5;
  const RunPlan plan = plan_runs({scene}, {}).at(0);
  ASSERT_TRUE(plan.seconds.has_value());
  EXPECT_EQ(*plan.seconds, 0.5);
  EXPECT_EQ(plan.samples, 0u);  // until the pilot chooses
  EXPECT_TRUE(plan.render != nullptr);
  for (const double bad : {0.0, -1.0, 2 * kMaxSecondsPerReplicate}) {
    scene.seconds = bad;
    EXPECT_TRUE(contains(plan_error({scene}), "out of range")) << bad;
  }
}

TEST(PlanBudget, FewerThanTwoReplicatesAreRejected) {
  for (std::uint32_t replicates : {0u, 1u}) {
    GridRequest r = row("genz-gaussian", {}, "where");
    r.replicates = replicates;
    const std::string message = plan_error({r});
    EXPECT_TRUE(contains(message, "where")) << message;
    EXPECT_TRUE(contains(message, "replicates = " + std::to_string(replicates))) << message;
  }
  BudgetDefaults forced;
  forced.forced_replicates = 1;
  EXPECT_TRUE(contains(plan_error({row("genz-gaussian")}, forced), "replicates = 1"));
}

// ---------------------------------------------------------------------------------------------
// Names, values and expectations

TEST(PlanNames, UnknownEstimatorListsTheValidOnes) {
  const std::string message = plan_error({grid({"plian"}, {"genz-gaussian"})});
  EXPECT_TRUE(contains(message, "unknown estimator 'plian'")) << message;
  EXPECT_TRUE(contains(message, "valid estimators: plain")) << message;
}

TEST(PlanNames, UnknownIntegrandListsTheValidOnes) {
  const std::string message = plan_error({row("genz-gausian")});
  EXPECT_TRUE(contains(message, "unknown integrand 'genz-gausian'")) << message;
  EXPECT_TRUE(contains(message, "valid integrands: genz-gaussian, genz-oscillatory,")) << message;
  EXPECT_TRUE(contains(message, ", expr")) << message;
}

// Names are looked up once, into registry rows that the plans then carry.
TEST(PlanNames, ResolvedOnceIntoTheRegistryRowsThePlansCarry) {
  const ResolvedGrid resolved = resolve_names(grid({"plain", "pcbpt"}, {"genz-gaussian"}));
  ASSERT_EQ(resolved.estimators.size(), 2u);
  ASSERT_EQ(resolved.integrands.size(), 1u);
  EXPECT_EQ(resolved.estimators[0], &find_estimator("plain"));
  EXPECT_EQ(resolved.estimators[1], &find_estimator("pcbpt"));
  EXPECT_EQ(resolved.integrands[0], &find_integrand("genz-gaussian"));
  const std::vector<RunPlan> plans = plan_runs({resolved}, {});
  ASSERT_EQ(plans.size(), 2u);
  EXPECT_EQ(plans[0].estimator, resolved.estimators[0]);
  EXPECT_EQ(plans[1].estimator, resolved.estimators[1]);
  EXPECT_EQ(plans[0].integrand, resolved.integrands[0]);
  // The same plans as from the names.
  EXPECT_EQ(plans[1].id, plan_runs({grid({"plain", "pcbpt"}, {"genz-gaussian"})}, {}).at(1).id);
}

// Another name of a row (plain's `bdpt`) is that row: a run asked for by it is the run asked for
// by the row's name, its id included, on scenes and on analytic integrands; both in one grid are
// one run.
TEST(PlanNames, AnAliasPlansTheRunsOfItsRow) {
  EXPECT_EQ(&find_estimator("bdpt"), &find_estimator("plain"));
  for (const std::string integrand : {"cornell", "genz-gaussian"}) {
    SCOPED_TRACE(integrand);
    const std::vector<RunPlan> alias = plan_runs({grid({"bdpt"}, {integrand})}, {});
    const std::vector<RunPlan> name = plan_runs({grid({"plain"}, {integrand})}, {});
    ASSERT_EQ(alias.size(), 1u);
    ASSERT_EQ(name.size(), 1u);
    EXPECT_EQ(alias[0].id, name[0].id);
    EXPECT_EQ(alias[0].estimator->name, "plain");
    EXPECT_EQ(plan_runs({grid({"plain", "bdpt"}, {integrand})}, {}).size(), 1u);
  }
  const std::string message = plan_error({grid({"bdtp"}, {"cornell"})});
  EXPECT_TRUE(contains(message, "did you mean 'bdpt'")) << message;
}

TEST(PlanNames, AnUnknownNameSaysWhereItWasGiven) {
  const std::string message =
      plan_error({grid({"plian"}, {"genz-gaussian"}, {}, "s.json: /runs/3")});
  EXPECT_TRUE(contains(message, "s.json: /runs/3: unknown estimator 'plian'")) << message;
}

TEST(PlanValues, BadParameterValueNamesWhereAndParameter) {
  const std::string message =
      plan_error({row("genz-gaussian", {{"sharpness", {"1", "abc"}}}, "suite.json: /grid/2")});
  EXPECT_TRUE(contains(message, "suite.json: /grid/2")) << message;
  EXPECT_TRUE(contains(message, "integrand 'genz-gaussian'")) << message;
  EXPECT_TRUE(contains(message, "'sharpness' = 'abc'")) << message;
}

TEST(PlanValues, MissingRequiredParameterIsRejected) {
  const std::string message = plan_error({row("expr")});
  EXPECT_TRUE(contains(message, "'f'")) << message;
  EXPECT_TRUE(contains(message, "required")) << message;
}

TEST(PlanValues, BadExpressionIsFoundWhilePlanning) {
  const std::string message = plan_error({row("expr", {{"f", {"x0*"}}}, "cli")});
  EXPECT_TRUE(contains(message, "cli: plain × expr")) << message;
  EXPECT_TRUE(contains(message, "parameter 'f'")) << message;
}

TEST(PlanExpect, ValidExpectationsPassThrough) {
  for (const std::string& expect : kExpectations) {
    GridRequest r = row("genz-gaussian");
    r.expect = expect;
    const std::vector<RunPlan> plans = plan_runs({r}, {});
    ASSERT_EQ(plans.size(), 1u);
    EXPECT_EQ(plans[0].expect, std::optional<std::string>(expect));
  }
  const std::vector<RunPlan> unset = plan_runs({row("genz-gaussian")}, {});
  EXPECT_FALSE(unset.at(0).expect.has_value());
}

// One rule for runs and exact checks: the row's expect wins; a test that cannot decide expects
// inconclusive (a control too); otherwise a control expects biased, an honest run consistent.
TEST(PlanExpect, OneDefaultRuleForEveryTest) {
  const RunPlan honest = plan_runs({row("genz-gaussian")}, {}).at(0);
  const RunPlan control = plan_runs({grid({"ctl-wrong-count"}, {"genz-gaussian"})}, {}).at(0);
  ASSERT_TRUE(control.estimator->biased);
  EXPECT_EQ(expected_result(honest, true), "consistent");
  EXPECT_EQ(expected_result(control, true), "biased");
  EXPECT_EQ(expected_result(honest, false), "inconclusive");
  EXPECT_EQ(expected_result(control, false), "inconclusive");
  GridRequest stated = grid({"ctl-wrong-count"}, {"genz-gaussian"});
  stated.expect = "consistent";
  const RunPlan stated_plan = plan_runs({stated}, {}).at(0);
  EXPECT_EQ(expected_result(stated_plan, true), "consistent");
  EXPECT_EQ(expected_result(stated_plan, false), "consistent");
}

TEST(PlanExpect, BadExpectationIsRejectedWithTheValidList) {
  GridRequest r = row("genz-gaussian", {}, "suite.json: /runs/4");
  r.expect = "consistant";
  const std::string message = plan_error({r});
  EXPECT_TRUE(contains(message, "suite.json: /runs/4")) << message;
  EXPECT_TRUE(contains(message, "'consistant'")) << message;
  EXPECT_TRUE(contains(message, "consistent, biased, inconclusive")) << message;
}

}  // namespace
}  // namespace pcbench
