// `pcbench list [--json]`: the registry tables, with parameters, defaults and descriptions.
#pragma once

#include <iosfwd>

namespace pcbench {

void print_registry(std::ostream& out, bool as_json);

}  // namespace pcbench
