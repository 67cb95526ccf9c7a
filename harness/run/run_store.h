// The journal of a session's finished runs, for `--resume`: DIR/checkpoint/ in the report folder
// holds session.json (the seed, the suite and the planned run ids, in plan order) and one
// <id>.json per finished run (harness/run/saved_run.h), each written atomically the moment the run
// finishes, so that a kill -9 loses at most the run that was running.
//
// A run is done, and is restored instead of run again, when its status is `ok` or `invalid`:
// both are pure functions of (seed, plan), so running them again would give the same bits.
// `error` and `not_run` runs are run again: an error may come from the machine (memory, a file)
// rather than the run, and a run that did not finish has nothing to restore.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/run/saved_run.h"

namespace pcbench {

class RunStore {
 public:
  // A new session's journal in folder/checkpoint/: removes the checkpoints of an earlier session
  // there (with a warning to `err`) and writes the manifest. Throws std::runtime_error if it
  // cannot.
  static RunStore start(const std::filesystem::path& folder, std::uint64_t seed,
                        const std::string& suite_name, const std::vector<RunPlan>& plans,
                        std::ostream& err);

  // `--resume`: reads folder/checkpoint/, checks that it was made with the same seed and the
  // same planned runs, and reads every saved run. Throws InputError naming the file (nothing is
  // written). Keeps writing new checkpoints to the same folder.
  static RunStore resume(const std::filesystem::path& folder, std::uint64_t seed,
                         const std::vector<RunPlan>& plans);

  // The saved run with this id, or null.
  const SavedRun* find(const std::string& id) const;
  // The same, counted as restored into the session's report.
  const SavedRun* restore(const std::string& id);
  std::uint64_t restored() const { return restored_; }

  // Saves a finished run (`ok` or `invalid`; other statuses are not saved). A checkpoint that
  // cannot be written costs only the ability to resume: a warning to `err`, not an error.
  void save(const RunPlan& plan, const RunResult& result, std::ostream& err);

  // The session finished and its report holds every run: the journal is removed.
  void discard(std::ostream& err);

  const std::filesystem::path& directory() const { return directory_; }
  std::filesystem::path file_of(const std::string& id) const;

 private:
  RunStore(std::filesystem::path directory, std::uint64_t seed)
      : directory_(std::move(directory)), seed_(seed) {}

  std::filesystem::path directory_;
  std::uint64_t seed_;
  std::map<std::string, SavedRun> saved_;
  std::uint64_t restored_ = 0;
  bool warned_ = false;
};

// Where a report folder's journal lives.
std::filesystem::path checkpoint_directory(const std::filesystem::path& folder);

}  // namespace pcbench
