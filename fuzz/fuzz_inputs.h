// The entry points that the fuzz targets (fuzz/*_fuzzer.cpp) and the regression test
// (tests/fuzz_regressions_test.cpp) feed hostile text to. Each runs what pcbench runs on that kind
// of input, from the text to the objects a run would use, so that input which parses but is bad
// (an unknown estimator, a scene that breaks the camera) is exercised too.
//
// Each returns kAccepted, or kRejected when pcbench would stop with an InputError (bad input,
// exit status 2). Any other exception escaping them is a bug, and so is a crash, a hang or a
// sanitizer report.
#pragma once

#include <filesystem>
#include <string_view>

namespace pcbench::fuzz {

enum class Outcome { kAccepted, kRejected };

// A suite file: parse_suite, then plan_runs with the suite's defaults, as `pcbench run SUITE`
// does before any run starts (every estimator and integrand of the plan is built). A scene file
// named as an integrand is looked up relative to the working directory.
Outcome check_suite_text(std::string_view text);

// A scene file: parse_scene_json with relative OBJ paths resolved in `scratch`, then, for scenes
// of at most kMaxFuzzTriangles triangles, the traced-ready Scene (BVH, emitters, camera, traits)
// and the furnace test. Text after a line "#obj" is written to scratch/mesh.obj first (and
// without one, scratch/mesh.obj is removed), so OBJ references are fuzzed with the scene.
inline constexpr std::size_t kMaxFuzzTriangles = 2000;
Outcome check_scene_text(std::string_view text, const std::filesystem::path& scratch);

// The expression `f` of the integrand 'expr' with light_dims = camera_dims = 2 (x0, x1, y0, y1),
// made through its registry entry as a suite row would make it, then copied (each thread's copy
// binds its own variables) and evaluated at the corners and centre of [0, 1]^4 and a few
// interior points. Muparser's bulk (OpenMP) mode is never used: pcbench does not use it.
Outcome check_expression_text(std::string_view text);

// The check for a target's name ("suite", "scene", "expression"); OBJ scratch files of "scene"
// go to `scratch`. Throws std::invalid_argument for an unknown name.
Outcome check_input(std::string_view target, std::string_view text,
                    const std::filesystem::path& scratch);

}  // namespace pcbench::fuzz
