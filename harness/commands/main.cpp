// The pcbench executable (harness/commands/entry_point.h).
#include "harness/commands/entry_point.h"

int main(int argc, char** argv) {
  return pcbench::run_main(argc, argv);
}
