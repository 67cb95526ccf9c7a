// Job arrays without MPI: `pcbench run|verify … --shard i/n --out DIR_i` runs a deterministic
// share of the planned runs and keeps them in DIR_i's resume journal (harness/run_store.h), and
// `pcbench merge DIR_0 … DIR_n-1 --out DIR` joins the journals and finishes the session from
// them, as `--resume` does: the family, escalation (its later stages run in the merge), the
// report and the images come out as one process would have written them, bit for bit.
//
// Run k of the plan (in plan order, counted from 0) belongs to shard k mod n: neighbouring rows
// of a suite, often the costly ones of one integrand, land in different shards.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/session/session.h"

namespace pcbench {

struct Shard {
  std::uint32_t index = 0;  // from 0
  std::uint32_t count = 1;
};

// "i/n" with 0 <= i < n; InputError otherwise (naming --shard).
Shard parse_shard(const std::string& text);

// The plans of this shard, in plan order.
std::vector<RunPlan> shard_share(const std::vector<RunPlan>& plans, const Shard& shard);

// Runs the shard's share into `folder`'s journal (options.resume: the journal, started or
// resumed over all the plans) and writes folder/shard.json: the shard, and `argv` (the command
// without --shard, --out and --resume) for `pcbench merge`. No report: one comes from the merge.
int run_shard(const std::vector<RunPlan>& plans, const Shard& shard, SessionOptions options,
              const std::filesystem::path& folder, const std::vector<std::string>& argv,
              std::ostream& out, std::ostream& err);

// The command line without the options that say where and which share (--shard, --out,
// --resume): what every shard of one job has alike.
std::vector<std::string> shared_arguments(const std::vector<std::string>& args);

// `pcbench merge`: checks the shard folders (every shard of one job, each once; InputError
// naming the missing ones, before anything is written), copies their journals into
// out/checkpoint/, and returns the command line that finishes the session from it (the shards'
// command with --out `out` --resume).
std::vector<std::string> merge_arguments(const std::vector<std::filesystem::path>& folders,
                                         const std::filesystem::path& out);

}  // namespace pcbench
