// "Did you mean" hints for messages about an unknown name from a closed set.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace pcbench {

// Edit distance counting a swap of neighbours as one edit (optimal string alignment), so that
// "qaud" is one edit from "quad".
std::size_t edit_distance(std::string_view a, std::string_view b);

// " (did you mean 'x'?)" for the choice nearest to `name`, if it is within a third of its own
// length (at least 1 edit); otherwise "". Ties go to the earlier choice.
std::string did_you_mean(std::string_view name, const std::vector<std::string>& choices);

}  // namespace pcbench
