#include "harness/plan/plan.h"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "base/errors.h"
#include "base/text_hash.h"

namespace pcbench {

const std::vector<std::string> kExpectations = {"consistent", "biased", "inconclusive"};

std::string expected_result(const RunPlan& plan, bool decidable) {
  if (plan.expect) return *plan.expect;
  if (!decidable) return "inconclusive";
  return plan.estimator->biased ? "biased" : "consistent";
}

namespace {

bool declares(const std::vector<ParamSpec>& specs, const std::string& key) {
  return std::any_of(specs.begin(), specs.end(),
                     [&](const ParamSpec& spec) { return spec.name == key; });
}

std::vector<std::string> spec_names(const std::vector<ParamSpec>& specs) {
  std::vector<std::string> names;
  for (const ParamSpec& spec : specs) names.push_back(spec.name);
  return names;
}

std::string names_or_none(const std::vector<ParamSpec>& specs) {
  return specs.empty() ? std::string("none") : join_names(spec_names(specs));
}

bool is_scene(const IntegrandEntry& integrand) {
  return integrand.has_tag("scene");
}

// The parameters `estimator` reads on `integrand`; InputError when it cannot run there.
const std::vector<ParamSpec>& estimator_specs(const EstimatorEntry& estimator,
                                              const IntegrandEntry& integrand,
                                              const std::string& where) {
  if (is_scene(integrand)) {
    if (!estimator.renders_scenes()) {
      std::vector<std::string> able;
      for (const EstimatorEntry& e : estimator_registry()) {
        if (e.renders_scenes()) able.push_back(e.name);
      }
      throw InputError(
          fmt::format("{}: estimator '{}' does not render scenes ('{}' is one); "
                      "estimators that do: {}",
                      where, estimator.name, integrand.name, join_names(able)));
    }
    return estimator.scene_params;
  }
  if (!estimator.samples_analytic()) {
    throw InputError(fmt::format("{}: estimator '{}' works on scenes only, not on '{}'", where,
                                 estimator.name, integrand.name));
  }
  return estimator.params;
}

struct Row {
  const EstimatorEntry* estimator;
  const IntegrandEntry* integrand;
  ParamText params;
};

[[noreturn]] void too_many_runs(const GridRequest& grid) {
  throw InputError(fmt::format(
      "{}: more than {} runs in all (a grid is the product of its lists); give fewer values",
      grid.where, kMaxRuns));
}

// Expands one grid into rows; a key the row's estimator and integrand do not read is dropped for
// that row, and a key no row reads is an error (a typo would otherwise vanish silently). Throws
// when the rows, with `earlier` rows of the grids before, would be more than kMaxRuns.
std::vector<Row> expand(const ResolvedGrid& resolved, std::size_t earlier) {
  const GridRequest& grid = resolved.request;
  if (resolved.estimators.empty()) throw InputError(grid.where + ": no estimator given");
  if (resolved.integrands.empty()) throw InputError(grid.where + ": no integrand given");
  std::vector<Row> rows;
  std::set<std::string> keys_read;
  for (const EstimatorEntry* estimator_entry : resolved.estimators) {
    const EstimatorEntry& estimator = *estimator_entry;
    for (const IntegrandEntry* integrand_entry : resolved.integrands) {
      const IntegrandEntry& integrand = *integrand_entry;
      const std::vector<ParamSpec>& specs = estimator_specs(estimator, integrand, grid.where);
      std::vector<ParamText> partial = {{}};
      for (const auto& [key, values] : grid.params) {
        if (!declares(specs, key) && !declares(integrand.params, key)) continue;
        keys_read.insert(key);
        if (values.empty())
          throw InputError(fmt::format("{}: parameter '{}' has no values", grid.where, key));
        if (earlier + rows.size() + partial.size() * values.size() > kMaxRuns) {
          too_many_runs(grid);
        }
        std::vector<ParamText> next;
        for (const ParamText& base : partial) {
          for (const std::string& value : values) {
            ParamText row = base;
            row[key] = value;
            next.push_back(std::move(row));
          }
        }
        partial = std::move(next);
      }
      if (earlier + rows.size() + partial.size() > kMaxRuns) too_many_runs(grid);
      for (ParamText& params : partial) rows.push_back({&estimator, &integrand, std::move(params)});
    }
  }
  for (const auto& [key, values] : grid.params) {
    if (keys_read.count(key)) continue;
    std::string readers;
    for (const EstimatorEntry* estimator : resolved.estimators) {
      readers += fmt::format("; estimator '{}' reads: {}", estimator->name,
                             names_or_none(estimator->params));
    }
    for (const IntegrandEntry* integrand : resolved.integrands) {
      readers += fmt::format("; integrand '{}' reads: {}", integrand->name,
                             names_or_none(integrand->params));
    }
    throw InputError(fmt::format("{}: parameter '{}' is read by no estimator or integrand{}",
                                 grid.where, key, readers));
  }
  return rows;
}

}  // namespace

ResolvedGrid resolve_names(GridRequest grid) {
  ResolvedGrid resolved;
  try {
    for (const std::string& name : grid.estimators) {
      resolved.estimators.push_back(&find_estimator(name));
    }
    for (const std::string& name : grid.integrands) {
      resolved.integrands.push_back(&find_integrand(name));
    }
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", grid.where, e.what()));
  }
  resolved.request = std::move(grid);
  return resolved;
}

std::vector<RunPlan> plan_runs(const std::vector<GridRequest>& grids,
                               const BudgetDefaults& budget) {
  std::vector<ResolvedGrid> resolved;
  for (const GridRequest& grid : grids) resolved.push_back(resolve_names(grid));
  return plan_runs(resolved, budget);
}

std::uint64_t default_samples(const IntegrandEntry& integrand) {
  return is_scene(integrand) ? kDefaultScenePixelSamples : kDefaultSamples;
}

std::uint64_t run_id_hash(const std::string& estimator, const std::string& integrand,
                          const std::map<std::string, std::string>& effective_params,
                          std::uint64_t samples, std::uint32_t replicates) {
  std::uint64_t hash = fnv1a(kFnvOffset, "pcbench-run-v1");
  hash = fnv1a(hash, estimator);
  hash = fnv1a(hash, integrand);
  for (const auto& [key, value] : effective_params) hash = fnv1a(fnv1a(hash, key), value);
  hash = fnv1a(hash, fmt::format("samples={}", samples));
  return fnv1a(hash, fmt::format("replicates={}", replicates));
}

void assign_id(RunPlan& plan) {
  std::map<std::string, std::string> effective;
  const std::vector<ParamSpec>& specs =
      is_scene(*plan.integrand) ? plan.estimator->scene_params : plan.estimator->params;
  for (const auto& entry : plan.estimator_params.values()) {
    // The pair, not a structured binding: clang 14 (the sanitizer build) cannot capture one.
    const std::string& key = entry.first;
    const auto spec =
        std::find_if(specs.begin(), specs.end(), [&](const ParamSpec& s) { return s.name == key; });
    const std::string text = to_text(entry.second);
    if (spec != specs.end() && spec->omitted_from_id_at == text) continue;
    effective[key] = text;
  }
  for (const auto& [key, value] : plan.integrand_params.values()) effective[key] = to_text(value);
  // No parameter name starts with '@': the budget cannot collide with a parameter.
  if (plan.seconds) effective["@seconds"] = fmt::format("{}", *plan.seconds);
  if (plan.pilot) effective["@pilot"] = "yes";
  if (plan.paired_streams) effective["@paired"] = "yes";
  plan.id_hash = run_id_hash(plan.estimator->name, plan.integrand->name, effective, plan.samples,
                             plan.replicates);
  plan.id = fmt::format("{:016x}", plan.id_hash);
  plan.stream_hash = plan.id_hash;
  if (plan.paired_streams) {
    // Everything of the id but the estimator and its params.
    std::map<std::string, std::string> scene;
    for (const auto& [key, value] : plan.integrand_params.values()) scene[key] = to_text(value);
    if (plan.pilot) scene["@pilot"] = "yes";
    plan.stream_hash =
        run_id_hash("@paired", plan.integrand->name, scene, plan.samples, plan.replicates);
  }
}

void pair_scene_streams(std::vector<RunPlan>& plans) {
  for (RunPlan& plan : plans) {
    if (!plan.render) continue;
    plan.paired_streams = true;
    assign_id(plan);
  }
}

RunPlan with_samples(const RunPlan& plan, std::uint64_t samples) {
  RunPlan next = plan;
  next.samples = samples;
  next.seconds.reset();
  assign_id(next);
  return next;
}

RunPlan with_chosen_samples(const RunPlan& plan, std::uint64_t samples) {
  RunPlan chosen = plan;
  chosen.samples = samples;
  const RunPlan streams = with_samples(plan, samples);
  chosen.id_hash = streams.id_hash;
  chosen.stream_hash = streams.stream_hash;
  return chosen;
}

namespace {

void check_expectation(const GridRequest& grid) {
  if (grid.expect &&
      std::find(kExpectations.begin(), kExpectations.end(), *grid.expect) == kExpectations.end()) {
    throw InputError(fmt::format("{}: expect '{}' is not valid; valid: {}", grid.where,
                                 *grid.expect, join_names(kExpectations)));
  }
}

// A budget within the limits: seconds per replicate in range, else samples in range; the camera
// samples of one run bounded; at least two replicates, since tests need their spread.
void check_budget(const RunPlan& plan, const std::string& where) {
  if (plan.seconds &&
      !(*plan.seconds >= kMinSecondsPerReplicate && *plan.seconds <= kMaxSecondsPerReplicate)) {
    throw InputError(fmt::format("{}: seconds = {} is out of range [{:g}, {:.0e}]", where,
                                 *plan.seconds, kMinSecondsPerReplicate, kMaxSecondsPerReplicate));
  }
  if (!plan.seconds && (plan.samples < 1 || plan.samples > kMaxSamples)) {
    throw InputError(
        fmt::format("{}: samples = {} is out of range [1, {}]", where, plan.samples, kMaxSamples));
  }
  // samples <= 2^32 and replicates < 2^32 here: the product fits in 64 bits.
  if (static_cast<double>(plan.total_samples()) > kMaxTotalSamples) {
    throw InputError(
        fmt::format("{}: samples × replicates = {} × {} exceeds {:.0e} camera samples in one run",
                    where, plan.samples, plan.replicates, kMaxTotalSamples));
  }
  if (plan.replicates < 2 || plan.replicates > kMaxReplicates) {
    throw InputError(fmt::format(
        "{}: replicates = {} is out of range [2, {}] (tests need the spread across at least "
        "two replicates)",
        where, plan.replicates, kMaxReplicates));
  }
}

// A run's budget, checked: samples and replicates from the command line, else the row, else the
// suite, else the integrand kind's default; an equal-time budget (seconds) leaves samples 0 for
// its pilot to choose.
void set_budget(RunPlan& plan, const GridRequest& grid, const BudgetDefaults& budget) {
  plan.samples = budget.forced_samples.value_or(
      grid.samples.value_or(budget.samples.value_or(default_samples(*plan.integrand))));
  plan.replicates = budget.forced_replicates.value_or(grid.replicates.value_or(budget.replicates));
  // Samples given on the command line win over any seconds; seconds on the command line
  // win over a suite's samples; within a suite a row's budget wins over the defaults.
  if (!budget.forced_samples) {
    plan.seconds = budget.forced_seconds;
    if (!plan.seconds && !grid.samples) plan.seconds = grid.seconds ? grid.seconds : budget.seconds;
  }
  if (plan.seconds) plan.samples = 0;
  check_budget(plan, grid.where);
}

// The plan of one row of a grid: its parameters resolved against the specs, its budget and
// expectation, its id; the estimator and integrand are not made yet.
RunPlan row_plan(const GridRequest& grid, const Row& row, const BudgetDefaults& budget) {
  RunPlan plan;
  plan.where = grid.where;
  plan.estimator = row.estimator;
  plan.integrand = row.integrand;
  plan.estimator_params = resolve_params(
      is_scene(*row.integrand) ? row.estimator->scene_params : row.estimator->params, row.params,
      fmt::format("{}: estimator '{}'", grid.where, row.estimator->name));
  plan.integrand_params =
      resolve_params(row.integrand->params, row.params,
                     fmt::format("{}: integrand '{}'", grid.where, row.integrand->name));
  set_budget(plan, grid, budget);
  plan.expect = grid.expect;
  assign_id(plan);
  return plan;
}

// The runs planned so far, by id, with the expectation and the grid of the first.
class SeenRuns {
 public:
  // Whether `plan` is the first with its id. Identical rows collapse into one; the same run
  // expected to give two different verdicts is a contradiction in the suite, not something to
  // settle by row order.
  bool first(const RunPlan& plan) {
    const auto [it, inserted] = seen_.emplace(plan.id_hash, Seen{plan.expect, plan.where});
    if (!inserted && it->second.expect != plan.expect) {
      throw InputError(fmt::format("{}: the same run as {} with a different expectation ({} vs {})",
                                   plan.where, it->second.where, plan.expect.value_or("default"),
                                   it->second.expect.value_or("default")));
    }
    return inserted;
  }

 private:
  struct Seen {
    std::optional<std::string> expect;
    std::string where;
  };
  std::map<std::uint64_t, Seen> seen_;
};

// The estimator (the renderer, on a scene) and the integrand a plan runs, made from its
// parameters; their InputError names the grid and the pair.
void make_objects(RunPlan& plan) {
  const std::string where =
      fmt::format("{}: {} × {}", plan.where, plan.estimator->name, plan.integrand->name);
  try {
    if (is_scene(*plan.integrand)) {
      plan.render = plan.estimator->make_render(plan.estimator_params);
    } else {
      plan.made_estimator = plan.estimator->make(plan.estimator_params);
    }
    plan.made_integrand = plan.integrand->make(plan.integrand_params);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", where, e.what()));
  }
}

}  // namespace

std::vector<RunPlan> plan_runs(const std::vector<ResolvedGrid>& grids,
                               const BudgetDefaults& budget) {
  std::vector<RunPlan> plans;
  SeenRuns seen;
  std::size_t rows_so_far = 0;  // before identical rows collapse: what expanding costs
  for (const ResolvedGrid& resolved : grids) {
    check_expectation(resolved.request);
    const std::vector<Row> rows = expand(resolved, rows_so_far);
    rows_so_far += rows.size();
    for (const Row& row : rows) {
      RunPlan plan = row_plan(resolved.request, row, budget);
      if (!seen.first(plan)) continue;
      make_objects(plan);
      plans.push_back(std::move(plan));
    }
  }
  return plans;
}

}  // namespace pcbench
