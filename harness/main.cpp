// The pcbench executable (harness/entry_point.h).
#include "harness/entry_point.h"

int main(int argc, char** argv) {
  return pcbench::run_main(argc, argv);
}
