// Dispatch by target name, for the regression test and the runner's replay (fuzz/fuzz_inputs.h).
#include "fuzz/fuzz_inputs.h"

#include <stdexcept>
#include <string>

namespace pcbench::fuzz {

Outcome check_input(std::string_view target, std::string_view text,
                    const std::filesystem::path& scratch) {
  if (target == "suite") return check_suite_text(text);
  if (target == "scene") return check_scene_text(text, scratch);
  if (target == "expression") return check_expression_text(text);
  throw std::invalid_argument("unknown fuzz target '" + std::string(target) +
                              "'; valid: suite, scene, expression");
}

}  // namespace pcbench::fuzz
