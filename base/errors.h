// Error kinds that decide the exit status (docs/reference/INTERFACE.md): bad input stops before any
// work and exits 2; a failure inside one run is recorded in that run and the suite goes on.
#pragma once

#include <stdexcept>
#include <string>

namespace pcbench {

// Bad input: a file, key, name or value the user supplied. The message names the location and,
// where there is a closed set, the valid choices.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Joins names as "a, b, c" for "valid choices" messages.
template <typename Range>
std::string join_names(const Range& names, const char* separator = ", ") {
  std::string out;
  for (const auto& name : names) {
    if (!out.empty()) out += separator;
    out += name;
  }
  return out;
}

}  // namespace pcbench
