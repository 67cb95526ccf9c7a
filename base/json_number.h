// Numbers into JSON, which has no NaN or infinity: every writer of a report section takes them
// from here, so that a non-finite number is written one way everywhere.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pcbench {

// A figure that may be undefined by design (no reference, an empty set): null where it is not
// finite.
inline nlohmann::ordered_json finite_or_null(double value) {
  return std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

// Writes the numbers of one record and remembers the path of every non-finite one: a report
// names them (a run's `nonfinite_fields`), because there a null is a result, a NaN or an
// infinity the run produced, not a figure left undefined.
class NumberWriter {
 public:
  nlohmann::ordered_json number(double value, const std::string& path) {
    if (std::isfinite(value)) return value;
    nonfinite_.push_back(path);
    return nullptr;
  }
  // A figure that is undefined by design: null, but not a non-finite result.
  static nlohmann::ordered_json optional_number(double value) { return finite_or_null(value); }
  const std::vector<std::string>& nonfinite() const { return nonfinite_; }

 private:
  std::vector<std::string> nonfinite_;
};

}  // namespace pcbench
