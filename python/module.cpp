// The extension `pcbench._pcbench`: the bindings the package pcbench (python/pcbench/) wraps.
// Every error of bad input is the harness's InputError, raised in Python as ValueError with its
// message; nothing here exits the interpreter.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <string_view>
#include <vector>

#include "base/errors.h"
#include "cli_call.h"
#include "results/context.h"
#include "verify_bindings.h"

namespace py = pybind11;

namespace {

// The CLI's message without its "command line: " (a Python call has none).
std::string python_message(std::string_view message) {
  constexpr std::string_view kPrefix = "command line: ";
  if (message.starts_with(kPrefix)) message.remove_prefix(kPrefix.size());
  return std::string(message);
}

}  // namespace

PYBIND11_MODULE(_pcbench, module) {
  module.doc() = "pcbench's harness, bound for the package pcbench (use that, not this)";
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const pcbench::InputError& e) {
      PyErr_SetString(PyExc_ValueError, python_message(e.what()).c_str());
    }
  });
  module.def(
      "_cli",
      [](const std::vector<std::string>& args, bool echo) {
        const pcbench::python::CliOutcome outcome = pcbench::python::call_cli(args, echo);
        return py::make_tuple(outcome.status, outcome.out, outcome.err);
      },
      py::arg("args"), py::arg("echo"),
      "runs `pcbench ARGS...` in this process: (status, stdout, stderr)");
  module.def("_version", &pcbench::pcbench_version, "pcbench's version");
  pcbench::python::add_verify_bindings(module);
}
