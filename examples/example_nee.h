// The worked example of docs/dev/extending.md "Adding a scene estimator" (example_nee.cpp).
#pragma once

#include "estimators/registry.h"

namespace pcbench::examples {

EstimatorEntry example_nee_entry();

}  // namespace pcbench::examples
