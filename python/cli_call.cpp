#include "cli_call.h"

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <future>
#include <iostream>
#include <optional>
#include <sstream>

#include "harness/commands/cli.h"

namespace pcbench::python {
namespace {

namespace py = pybind11;

// How often the waiting thread looks at Python's signals: a Ctrl-C is seen within this.
constexpr std::chrono::milliseconds kSignalPoll{50};

}  // namespace

CliOutcome call_cli(const std::vector<std::string>& args, bool echo) {
  std::ostringstream out, err;
  std::atomic<bool> interrupted{false};
  std::optional<py::error_already_set> raised;
  int status = 0;
  {
    const py::gil_scoped_release release;
    std::future<int> command = std::async(std::launch::async, [&] {
      return run_cli(args, echo ? std::cout : static_cast<std::ostream&>(out), err, &interrupted);
    });
    while (command.wait_for(kSignalPoll) != std::future_status::ready) {
      const py::gil_scoped_acquire acquire;
      // Python's SIGINT handler only sets a flag; this runs it (KeyboardInterrupt) in the main
      // thread. The command then finishes as after the CLI's own Ctrl-C.
      if (!raised && PyErr_CheckSignals() != 0) {
        raised.emplace();
        interrupted.store(true);
      }
    }
    status = command.get();
  }
  if (raised) throw *raised;
  return {.status = status, .out = out.str(), .err = err.str()};
}

}  // namespace pcbench::python
