// pcbench_examples: pcbench with the example estimators registered (examples/examples.cpp), so
// that `pcbench_examples list`, `run` and `verify` know them while pcbench itself does not
// (docs/dev/extending.md "Adding a scene estimator").
#include <utility>

#include "estimators/registry.h"
#include "examples/examples.h"
#include "harness/commands/entry_point.h"

int main(int argc, char** argv) {
  for (pcbench::EstimatorEntry& entry : pcbench::examples::example_entries()) {
    pcbench::register_scene_estimator(std::move(entry));
  }
  return pcbench::run_main(argc, argv);
}
