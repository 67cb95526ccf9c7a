// Runs another program (the plotting script) with its output forwarded to our streams, so that
// callers that capture pcbench's output (tests, embedding) see the child's too.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace pcbench {

// Runs argv[0] (a path; no PATH search) with argv, forwarding its standard output to `out` and
// its standard error to `err` as they arrive. Returns its exit status, 128 + the signal if it
// was killed, or -1 (after writing the reason to `err`) when it could not be started.
int run_child_process(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err);

}  // namespace pcbench
