// `pcbench reference`: renders converged images of scenes into the reference cache
// (harness/verify/reference_cache.h), for the RMSE and relative MSE of later scene runs.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "harness/commands/command_options.h"
#include "harness/plan/plan.h"
#include "harness/run/replicate_farm.h"
#include "harness/run/runner.h"
#include "harness/verify/reference_cache.h"

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

// The command line: scenes and the estimator and budget that render their converged images.
struct ReferenceArguments {
  std::vector<std::string> integrands;
  std::vector<std::string> estimators;  // default plain
  std::vector<std::string> params;      // key=value
  std::uint64_t samples = 0;            // default 256
  std::uint32_t replicates = 0;         // default 8
  std::uint64_t seed = kDefaultSeed;
  unsigned threads = 0;
  std::string reference_cache = kDefaultReferenceCache;
};

// Adds `reference` and its options to `app`.
CLI::App* add_reference_command(CLI::App& app, ReferenceArguments& args);

// `pcbench reference`: plans the images (every rank of an MPI job alike) and renders them.
int reference_command(const ReferenceArguments& args, const CommandContext& context);

}  // namespace pcbench
