// From what the user asked for (suite rows, grids, command-line flags) to validated run plans.
//
// Everything that can be wrong with the input is found here, before any run starts: unknown
// estimator or integrand names, parameter keys read by neither, values of the wrong type, an
// expression that does not parse. Each error names its location and the valid choices.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimators/registry.h"
#include "integrands/registry.h"

namespace pcbench {

inline constexpr std::uint64_t kDefaultSamples = 100000;
inline constexpr std::uint32_t kDefaultReplicates = 32;
inline constexpr std::uint64_t kDefaultSeed = 1;
// Counter layout limits of the random streams (harness/rng.h).
inline constexpr std::uint64_t kMaxSamples = 0xFFFFFFFFull;
inline constexpr std::uint32_t kMaxReplicates = 0xFFFFFFu;
// 10^13 camera samples would take weeks here; a budget beyond it is a typo.
inline constexpr double kMaxTotalSamples = 1e13;

// A grid: the product of its lists. A plain suite row is a grid whose lists have one element.
struct GridRequest {
  std::vector<std::string> estimators = {};
  std::vector<std::string> integrands = {};
  std::map<std::string, std::vector<std::string>> params = {};  // key -> values, as text
  std::optional<std::uint64_t> samples = {};
  std::optional<std::uint32_t> replicates = {};
  std::optional<std::string> expect = {};
  std::string where = {};  // "suites/x.json: /grid/0" or "command line"
};

// Budget settings that apply unless a row sets its own; `forced` values (from the command line)
// override rows too.
struct BudgetDefaults {
  std::uint64_t samples = kDefaultSamples;
  std::uint32_t replicates = kDefaultReplicates;
  std::optional<std::uint64_t> forced_samples = {};
  std::optional<std::uint32_t> forced_replicates = {};
};

struct RunPlan {
  std::string id;  // 16 hex digits of id_hash
  std::uint64_t id_hash = 0;
  std::string where;
  const EstimatorEntry* estimator = nullptr;
  const IntegrandEntry* integrand = nullptr;
  ResolvedParams estimator_params;
  ResolvedParams integrand_params;
  std::uint64_t samples = 0;
  std::uint32_t replicates = 0;
  std::optional<std::string> expect;  // unset: "consistent" if there is a reference
  std::shared_ptr<const Estimator> made_estimator;
  std::shared_ptr<const Integrand> made_integrand;
};

// Expands every grid, resolves and builds each row, and collapses rows with the same id (the
// first occurrence stays). Throws InputError on the first bad input.
std::vector<RunPlan> plan_runs(const std::vector<GridRequest>& grids, const BudgetDefaults& budget);

// Sets plan.id_hash and plan.id from its estimator, integrand, effective params and budget.
void assign_id(RunPlan& plan);

// The same run with another budget: a new id, so new random numbers (sequential escalation).
RunPlan with_samples(const RunPlan& plan, std::uint64_t samples);

// The id of a run: a hash of estimator, integrand, effective params, samples and replicates.
std::uint64_t run_id_hash(const std::string& estimator, const std::string& integrand,
                          const std::map<std::string, std::string>& effective_params,
                          std::uint64_t samples, std::uint32_t replicates);

extern const std::vector<std::string> kExpectations;  // consistent, biased, inconclusive

}  // namespace pcbench
