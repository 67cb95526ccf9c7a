// The pcbench command line called from Python: the CLI's own run_cli on a worker thread while the
// calling thread, without the GIL, polls Python's signal handlers, so that Ctrl-C
// (KeyboardInterrupt) stops a run as it stops the command (the report of the finished runs,
// status 130) and is raised once the command has returned.
#pragma once

#include <string>
#include <vector>

namespace pcbench::python {

struct CliOutcome {
  int status = 0;
  std::string out;  // what the command printed on stdout (empty when `echo`: it went there)
  std::string err;  // on stderr, always kept (its last line is the error of a status 2)
};

// Runs `pcbench ARGS...`; with `echo` its stdout goes to the process's stdout as it is printed.
// Throws pybind11::error_already_set (KeyboardInterrupt) after an interrupted command returned.
CliOutcome call_cli(const std::vector<std::string>& args, bool echo);

}  // namespace pcbench::python
