// What a pcbench executable's main() does: the command line on the standard streams, with
// Ctrl-C handling (finish the report of the runs that finished, exit 130).
// harness/commands/main.cpp is pcbench; examples/main.cpp is the same with example estimators
// registered first.
#pragma once

namespace pcbench {

int run_main(int argc, char** argv);

}  // namespace pcbench
