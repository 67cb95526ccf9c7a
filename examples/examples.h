// The example estimators (docs/dev/extending.md "Adding a scene estimator"): pcbench_examples
// registers them (examples/main.cpp) and tests/scene_mis_test.cpp checks them with the
// registry's; `pcbench list` does not show them.
#pragma once

#include <vector>

#include "estimators/registry.h"

namespace pcbench::examples {

std::vector<EstimatorEntry> example_entries();

}  // namespace pcbench::examples
