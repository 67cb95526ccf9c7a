// The examples' registry: one line each, the function the example's file defines, as
// estimators/registry.cpp lists pcbench's estimators (a new line goes above the last).
#include "examples/examples.h"

namespace pcbench::examples {

#define PCBENCH_EXAMPLES(ESTIMATOR) \
  ESTIMATOR(example_nee_entry) \
  /* the end of the list */

PCBENCH_EXAMPLES(PCBENCH_DECLARE_ENTRY)

std::vector<EstimatorEntry> example_entries() {
  return {PCBENCH_EXAMPLES(PCBENCH_CALL_ENTRY)};
}

}  // namespace pcbench::examples
