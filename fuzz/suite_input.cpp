// Suite text to run plans (fuzz/fuzz_inputs.h).
#include <string>

#include "base/errors.h"
#include "fuzz/fuzz_inputs.h"
#include "harness/plan/plan.h"
#include "harness/plan/suite_file.h"

namespace pcbench::fuzz {

Outcome check_suite_text(std::string_view text) {
  try {
    const SuiteRequest suite = parse_suite(std::string(text), "fuzz.json");
    // The suite's defaults as `pcbench run SUITE` applies them (harness/commands/run_command.cpp),
    // with no command-line overrides.
    BudgetDefaults budget;
    budget.samples = suite.samples;
    if (suite.replicates) budget.replicates = *suite.replicates;
    budget.seconds = suite.seconds;
    plan_runs(suite.grids, budget);
  } catch (const InputError&) {
    return Outcome::kRejected;
  }
  return Outcome::kAccepted;
}

}  // namespace pcbench::fuzz
