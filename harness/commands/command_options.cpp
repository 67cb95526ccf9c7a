#include "harness/commands/command_options.h"

#include <fmt/format.h>
#include <oneapi/tbb/info.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <limits>
#include <system_error>

#include "base/errors.h"

namespace pcbench {

SessionOptions session_options(const ReportArguments& args, const CommandContext& context) {
  SessionOptions session;
  session.seed = args.seed;
  session.threads = thread_count(args.threads);
  session.quiet = args.quiet;
  session.argv = context.argv;
  session.interrupted = context.interrupted;
  session.alpha = args.alpha;
  if (!args.out_dir.empty()) session.out_dir = args.out_dir;
  return session;
}

unsigned thread_count(unsigned threads) {
  return threads > 0 ? threads : static_cast<unsigned>(tbb::info::default_concurrency());
}

CLI::Validator alpha_check() {
  return CLI::Validator(
      [](std::string& text) {
        double a = 0.0;
        std::size_t used = 0;
        try {
          a = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || used == 0)
          return std::string("alpha must be a number in (0, 1)");
        return a > 0.0 && a < 1.0 ? std::string() : std::string("alpha must be in (0, 1)");
      },
      "in (0, 1)");
}

CLI::Option* add_seed_option(CLI::App* app, std::uint64_t& seed, const char* description) {
  return app->add_option("--seed,-s", seed, description)
      ->check(CLI::Range(std::uint64_t{0},
                         static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())));
}

void add_seed_and_threads_options(CLI::App* app, std::uint64_t& seed, unsigned& threads) {
  add_seed_option(app, seed, "seed (default 1)");
  app->add_option("--threads,-t", threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1u, 1024u));
}

void add_reference_cache_option(CLI::App* app, std::string& reference_cache) {
  app->add_option("--reference-cache", reference_cache,
                  "folder of converged scene images (default results/references)");
}

void check_out_dir(const std::string& out_dir, bool given) {
  if (given && out_dir.empty()) throw InputError("command line: --out is empty; give a folder");
  if (out_dir.empty()) return;
  if (std::filesystem::exists(out_dir) && !std::filesystem::is_directory(out_dir)) {
    throw InputError(fmt::format("command line: --out '{}' exists and is not a folder", out_dir));
  }
}

void create_out_dir(const std::string& out_dir) {
  if (out_dir.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) {
    throw InputError(
        fmt::format("command line: --out '{}' cannot be created: {}", out_dir, error.message()));
  }
}

void prepare_out_dir(const std::string& out_dir, bool given) {
  check_out_dir(out_dir, given);
  create_out_dir(out_dir);
}

}  // namespace pcbench
