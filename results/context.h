// The `context` block of a report: where, when and with what a report was made.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pcbench {

struct Context {
  std::string date;  // ISO 8601, UTC
  std::string host;
  std::string cpu;
  unsigned cores = 0;
  std::string compiler;
  std::string flags;
  std::string build_type;
  std::string git_commit;  // "unknown" outside a git checkout
  std::string git_dirty;   // "true", "false" or "unknown"
  std::vector<std::string> argv;
  std::uint64_t seed = 0;
  unsigned threads = 0;
  std::string version;
  // --resume: how many of the report's runs were restored from the interrupted session's
  // checkpoints (their timings are that session's).
  std::optional<std::uint64_t> restored_runs = {};
  // Under MPI (harness/run/replicate_farm.h): the ranks that computed the replicates; `threads` is
  // rank 0's, and `host` and `cpu` are rank 0's machine.
  std::optional<int> ranks = {};
};

Context gather_context(std::vector<std::string> argv, std::uint64_t seed, unsigned threads);

const char* pcbench_version();

}  // namespace pcbench
