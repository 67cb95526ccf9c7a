#include "harness/session/shard.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "base/text_file.h"
#include "harness/run/run_store.h"
#include "harness/session/report.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* kShardFormat = "pcbench-shard";
constexpr int kShardVersion = 1;

fs::path shard_file(const fs::path& folder) {
  return folder / "shard.json";
}

std::string shard_name(std::uint32_t index, std::uint32_t count) {
  return fmt::format("{}/{}", index, count);
}

// The options that say where and which share, with whether each takes a value.
bool is_placement(const std::string& arg, bool& takes_value) {
  for (const char* name : {"--shard", "--out", "-o"}) {
    if (arg == name) {
      takes_value = true;
      return true;
    }
    if (arg.rfind(std::string(name) + "=", 0) == 0) {
      takes_value = false;
      return true;
    }
  }
  takes_value = false;
  return arg == "--resume";
}

struct ShardRecord {
  fs::path folder;
  Shard shard;
  std::vector<std::string> args;
};

ShardRecord read_shard(const fs::path& folder) {
  const fs::path file = shard_file(folder);
  std::error_code error;
  if (!fs::exists(file, error)) {
    throw InputError(
        fmt::format("{}: not found: '{}' is not the --out folder of a finished `--shard i/n` run",
                    file.string(), folder.string()));
  }
  const std::string text = read_text_file(file, "the shard record");
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    if (j.at("format") != kShardFormat || j.at("version") != kShardVersion) {
      throw std::runtime_error(
          fmt::format("expected format {} version {}", kShardFormat, kShardVersion));
    }
    ShardRecord record{.folder = folder,
                       .shard = {.index = j.at("shard").get<std::uint32_t>(),
                                 .count = j.at("of").get<std::uint32_t>()},
                       .args = j.at("args").get<std::vector<std::string>>()};
    if (record.shard.count == 0 || record.shard.index >= record.shard.count) {
      throw std::runtime_error("shard index out of range");
    }
    return record;
  } catch (const std::exception& e) {
    throw InputError(
        fmt::format("{}: not a shard this pcbench can merge: {}", file.string(), e.what()));
  }
}

}  // namespace

Shard parse_shard(const std::string& text) {
  const auto fail = [&] {
    return InputError(fmt::format(
        "command line: --shard '{}': give i/n, this run's share i (0 to n-1) of n shards, e.g. "
        "--shard 0/4 (with Slurm: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)",
        text));
  };
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) throw fail();
  Shard shard;
  const char* end = text.data() + text.size();
  const auto first = std::from_chars(text.data(), text.data() + slash, shard.index);
  const auto second = std::from_chars(text.data() + slash + 1, end, shard.count);
  if (first.ec != std::errc() || first.ptr != text.data() + slash || second.ec != std::errc() ||
      second.ptr != end || shard.count == 0 || shard.index >= shard.count) {
    throw fail();
  }
  return shard;
}

std::vector<RunPlan> shard_share(const std::vector<RunPlan>& plans, const Shard& shard) {
  std::vector<RunPlan> share;
  for (std::size_t k = shard.index; k < plans.size(); k += shard.count) share.push_back(plans[k]);
  return share;
}

std::vector<std::string> shared_arguments(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    bool takes_value = false;
    if (is_placement(args[i], takes_value)) {
      if (takes_value) ++i;
      continue;
    }
    out.push_back(args[i]);
  }
  return out;
}

int run_shard(const std::vector<RunPlan>& plans, const Shard& shard, SessionOptions options,
              const fs::path& folder, const std::vector<std::string>& argv, std::ostream& out,
              std::ostream& err) {
  const std::vector<RunPlan> share = shard_share(plans, shard);
  const nlohmann::ordered_json record{{"format", kShardFormat},
                                      {"version", kShardVersion},
                                      {"shard", shard.index},
                                      {"of", shard.count},
                                      {"args", argv}};
  // Written first and removed never: a shard stopped early is still named by its folder, and
  // `--resume` finishes it.
  write_file_atomically(shard_file(folder), record.dump(2) + "\n");
  options.journal_only = true;
  const int status = run_session(share, options, out, err);
  if (status == kExitOk) {
    out << fmt::format(
        "shard {}: {} of {} runs saved in {}; `pcbench merge` the {} shard folders for the "
        "report\n",
        shard_name(shard.index, shard.count), share.size(), plans.size(),
        checkpoint_directory(folder).string(), shard.count);
  }
  return status;
}

std::vector<std::string> merge_arguments(const std::vector<fs::path>& folders,
                                         const fs::path& out) {
  if (folders.empty()) throw InputError("command line: merge: give the shards' --out folders");
  std::vector<ShardRecord> shards;
  for (const fs::path& folder : folders) shards.push_back(read_shard(folder));
  const ShardRecord& first = shards.front();
  std::map<std::uint32_t, const ShardRecord*> by_index;
  for (const ShardRecord& s : shards) {
    if (s.shard.count != first.shard.count || s.args != first.args) {
      throw InputError(fmt::format(
          "{}: shard {} of another job than {} (another command or number of shards); merge the "
          "shards of one job",
          shard_file(s.folder).string(), shard_name(s.shard.index, s.shard.count),
          shard_file(first.folder).string()));
    }
    const auto [it, added] = by_index.emplace(s.shard.index, &s);
    if (!added) {
      throw InputError(fmt::format("{} and {}: both hold shard {}; give each shard once",
                                   it->second->folder.string(), s.folder.string(),
                                   shard_name(s.shard.index, s.shard.count)));
    }
  }
  std::vector<std::string> missing;
  for (std::uint32_t i = 0; i < first.shard.count; ++i) {
    if (!by_index.contains(i)) missing.push_back(shard_name(i, first.shard.count));
  }
  if (!missing.empty()) {
    std::string names;
    for (const std::string& m : missing) names += (names.empty() ? "" : ", ") + m;
    throw InputError(fmt::format(
        "merge: missing shard{} {}: run `pcbench {} --shard I/{} --out DIR` for each, then merge "
        "again with their folders",
        missing.size() > 1 ? "s" : "", names, fmt::join(first.args, " "), first.shard.count));
  }
  for (const ShardRecord& s : shards) {
    if (!fs::exists(checkpoint_directory(s.folder) / "session.json")) {
      throw InputError(fmt::format("{}: no journal: shard {} did not start; run it again",
                                   checkpoint_directory(s.folder).string(),
                                   shard_name(s.shard.index, s.shard.count)));
    }
  }
  // Every shard planned the same runs (same command): one manifest, the union of the saved runs.
  const fs::path journal = checkpoint_directory(out);
  fs::create_directories(journal);
  fs::copy_file(checkpoint_directory(first.folder) / "session.json", journal / "session.json",
                fs::copy_options::overwrite_existing);
  for (const ShardRecord& s : shards) {
    for (const fs::directory_entry& entry :
         fs::directory_iterator(checkpoint_directory(s.folder))) {
      if (entry.path().filename() == "session.json" || entry.path().extension() != ".json") {
        continue;
      }
      fs::copy_file(entry.path(), journal / entry.path().filename(),
                    fs::copy_options::overwrite_existing);
    }
  }
  std::vector<std::string> args = first.args;
  args.insert(args.end(), {"--out", out.string(), "--resume"});
  return args;
}

}  // namespace pcbench
