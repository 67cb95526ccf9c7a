// pcbench_examples: pcbench with the example estimators registered, so that `pcbench_examples
// list`, `run` and `verify` know them while pcbench itself does not (docs/dev/extending.md "Adding
// a scene estimator").
#include "estimators/registry.h"
#include "examples/example_nee.h"
#include "harness/commands/entry_point.h"

int main(int argc, char** argv) {
  pcbench::register_scene_estimator(pcbench::examples::example_nee_entry());
  return pcbench::run_main(argc, argv);
}
