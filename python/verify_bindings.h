// The Python module's verifications of data in memory: `_verify_images` (numpy replicate images
// or image files, as `pcbench verify --images`) and `_verify_estimates` (1-D replicate
// estimates, as `verify --estimates`). Each builds the CLI's request, checks and tests it with
// the CLI's own functions (harness/commands/image_set_verify.h, external_verify.h) and returns
// the report the CLI would write: as written into `out`, or built in memory when there is none.
// The Python side (pcbench/_api.py) documents and wraps them.
#pragma once

#include <pybind11/pybind11.h>

namespace pcbench::python {

void add_verify_bindings(pybind11::module_& module);

}  // namespace pcbench::python
