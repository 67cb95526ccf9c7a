// Runs one scene plan: R replicates, each an image of `samples` iterations (samples per pixel).
// A replicate's scalar estimate is its image mean (pixels and channels), so the tests and
// aggregates of analytic runs apply to it; the images themselves go to the tile tests and the
// EXR files (harness/verify/scene_verification.h).
#pragma once

#include "harness/run/runner.h"

namespace pcbench {

RunResult execute_scene_run(const RunPlan& plan, const RunnerOptions& options);

}  // namespace pcbench
