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

namespace pcbench {

struct ReferenceOptions {
  std::uint64_t seed = 1;
  std::filesystem::path cache;
  std::vector<std::string> argv;
  const std::atomic<bool>* interrupted = nullptr;
};

// Renders each planned scene run and stores its mean and standard error unless the cache holds
// a better-converged image of that scene. Every plan must be a scene run of an honest estimator
// that samples all of the scene's light-carrying paths (InputError otherwise). Returns the exit
// status: 0 when every image was rendered, 3 when one failed or was interrupted.
int run_reference_command(const std::vector<RunPlan>& plans, const ReferenceOptions& options,
                          std::ostream& out, std::ostream& err);

}  // namespace pcbench
