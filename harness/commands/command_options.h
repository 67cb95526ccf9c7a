// What the commands share on the command line: the context a command runs in, the seed, threads
// and output options, and --out's checks.
#pragma once

#include <atomic>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/session/session.h"
#include "harness/verify/statistics.h"

namespace CLI {
class App;
class Option;
class Validator;
}  // namespace CLI

namespace pcbench {

// What a command runs with, besides its own arguments.
struct CommandContext {
  const CLI::App& app;            // the command's subcommand: which options were given
  std::vector<std::string> argv;  // "pcbench" and the arguments, for the report
  std::ostream& out;
  std::ostream& err;
  const std::atomic<bool>* interrupted = nullptr;  // polled between chunks of work
};

// What every command that writes a report takes alike; session_options makes them the
// session's options.
struct ReportArguments {
  std::uint64_t seed = kDefaultSeed;
  unsigned threads = 0;  // 0: all cores
  std::string out_dir;
  bool quiet = false;
  double alpha = kDefaultAlpha;
};

// Seed, threads, output, quiet, alpha, argv and the interrupt flag as a session's options; the
// rest at their defaults.
SessionOptions session_options(const ReportArguments& args, const CommandContext& context);

// --threads, or all cores.
unsigned thread_count(unsigned threads);

// A family-wise alpha: strictly between 0 and 1.
CLI::Validator alpha_check();

// --seed,-s. Seeds are written to reports as JSON integers, which readers may hold in an int64.
CLI::Option* add_seed_option(CLI::App* app, std::uint64_t& seed, const char* description);

// --seed,-s (default 1) and --threads,-t.
void add_seed_and_threads_options(CLI::App* app, std::uint64_t& seed, unsigned& threads);

// --reference-cache.
void add_reference_cache_option(CLI::App* app, std::string& reference_cache);

// Checks --out without creating anything (`given`: whether --out was on the command line).
void check_out_dir(const std::string& out_dir, bool given);

// Creates the checked --out folder, if one was given; InputError if it cannot.
void create_out_dir(const std::string& out_dir);

// Checks --out and creates the folder now, so that a report that cannot be written fails before
// any run, not after. (The input is valid by then: creating it writes nothing half-done.)
void prepare_out_dir(const std::string& out_dir, bool given);

}  // namespace pcbench
