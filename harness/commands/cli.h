// The `pcbench` command line (docs/reference/INTERFACE.md, "CLI"). Returns the exit status.
#pragma once

#include <atomic>
#include <iosfwd>
#include <string>
#include <vector>

namespace pcbench {

// `args` excludes the program name. `interrupted` is polled between chunks of work.
int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
            const std::atomic<bool>* interrupted = nullptr);

}  // namespace pcbench
