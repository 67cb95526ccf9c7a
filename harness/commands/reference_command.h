// `pcbench reference`: renders converged images of scenes into the reference cache
// (harness/verify/reference_cache.h), for the RMSE and relative MSE of later scene runs.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/run/replicate_farm.h"
#include "harness/run/runner.h"

namespace pcbench {

struct ReferenceOptions {
  // Seed and interrupt flag, built once for every image of the command.
  RunnerOptions runner;
  std::filesystem::path cache;
  std::vector<std::string> argv;
  ReplicateFarm* farm = nullptr;  // rank 0 of an MPI job: the replicates over all ranks
};

// Renders each planned scene run and stores its mean and standard error unless the cache holds
// a better-converged image of that scene. Every plan must be a scene run of an honest estimator
// that samples all of the scene's light-carrying paths (InputError otherwise). Returns the exit
// status: 0 when every image was rendered, 3 when one failed or was interrupted.
int run_reference_command(const std::vector<RunPlan>& plans, const ReferenceOptions& options,
                          std::ostream& out, std::ostream& err);

}  // namespace pcbench
