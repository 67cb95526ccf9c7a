#include "harness/run/run_store.h"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <nlohmann/json.hpp>
#include <ostream>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "base/text_file.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* kManifestFormat = "pcbench-session";
constexpr int kManifestVersion = 1;

fs::path manifest_path(const fs::path& directory) {
  return directory / "session.json";
}

// A saved run's file name: its 16-hex-digit id and ".json" (temporary files end otherwise).
bool is_saved_run_file(const fs::path& file) {
  const std::string stem = file.stem().string();
  return file.extension() == ".json" && stem.size() == 16 &&
         stem.find_first_not_of("0123456789abcdef") == std::string::npos;
}

std::string describe(const nlohmann::json& run) {
  return fmt::format("{} ({} × {})", run.at("id").get<std::string>(),
                     run.at("estimator").get<std::string>(),
                     run.at("integrand").get<std::string>());
}

// The manifest must name the same runs in the same order: another suite, selection or budget
// gives other ids, and restoring some of its runs into this report would be wrong.
void check_same_runs(const nlohmann::json& saved, const std::vector<RunPlan>& plans,
                     const fs::path& manifest) {
  const std::size_t n = std::max(saved.size(), plans.size());
  for (std::size_t i = 0; i < n; ++i) {
    const bool both = i < saved.size() && i < plans.size();
    if (both && saved[i].at("id") == plans[i].id) continue;
    const std::string was = i < saved.size() ? describe(saved[i]) : "no run";
    const std::string now = i < plans.size()
                                ? fmt::format("{} ({} × {})", plans[i].id, plans[i].estimator->name,
                                              plans[i].integrand->name)
                                : "no run";
    throw InputError(fmt::format(
        "{}: the interrupted session planned {} runs, this command plans {}; run {} was {}, "
        "now {}. Resume with the same suite or selection and budget (--samples, --replicates, "
        "--param), or write to another --out",
        manifest.string(), saved.size(), plans.size(), i + 1, was, now));
  }
}

SavedRun read_checked(const fs::path& file, std::uint64_t seed, const std::vector<RunPlan>& plans) {
  const std::string text = read_text_file(file, "the saved run");
  SavedRun run;
  try {
    run = read_saved_run(text);
  } catch (const std::exception& e) {
    throw InputError(
        fmt::format("{}: not a saved run this pcbench can read: {}", file.string(), e.what()));
  }
  const std::string stem = file.stem().string();
  if (run.id != stem) {
    throw InputError(fmt::format("{}: holds run {}, not {}", file.string(), run.id, stem));
  }
  if (run.seed != seed) {
    throw InputError(fmt::format(
        "{}: saved with seed {}, this session's seed is {}; resume with --seed {}, or write to "
        "another --out",
        file.string(), run.seed, seed, run.seed));
  }
  if (run.result.status != RunStatus::kOk && run.result.status != RunStatus::kInvalid) {
    throw InputError(fmt::format("{}: status {}; only ok and invalid runs are saved", file.string(),
                                 to_string(run.result.status)));
  }
  const auto plan =
      std::find_if(plans.begin(), plans.end(), [&](const RunPlan& p) { return p.id == run.id; });
  const bool budget_differs =
      plan != plans.end() &&
      (run.replicates != plan->replicates || (!plan->seconds && run.samples != plan->samples));
  if (budget_differs || run.result.replicates.size() != run.replicates) {
    throw InputError(
        fmt::format("{}: its samples and replicates do not match run {}", file.string(), run.id));
  }
  return run;
}

}  // namespace

fs::path checkpoint_directory(const fs::path& folder) {
  return folder / "checkpoint";
}

fs::path RunStore::file_of(const std::string& id) const {
  return directory_ / (id + ".json");
}

RunStore RunStore::start(const fs::path& folder, std::uint64_t seed, const std::string& suite_name,
                         const std::vector<RunPlan>& plans, std::ostream& err) {
  RunStore store(checkpoint_directory(folder), seed);
  // Only pcbench's own folder is removed: checkpoints of another session must not be restored
  // into this one.
  if (fs::exists(manifest_path(store.directory_))) {
    err << fmt::format(
        "pcbench: warning: {} held the finished runs of an interrupted session; they are removed "
        "(--resume would have continued it)\n",
        store.directory_.string());
  }
  fs::remove_all(store.directory_);
  fs::create_directories(store.directory_);
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const RunPlan& plan : plans) {
    runs.push_back({{"id", plan.id},
                    {"estimator", plan.estimator->name},
                    {"integrand", plan.integrand->name}});
  }
  const nlohmann::ordered_json manifest{{"format", kManifestFormat},
                                        {"version", kManifestVersion},
                                        {"seed", seed},
                                        {"suite", suite_name},
                                        {"runs", runs}};
  write_file_atomically(manifest_path(store.directory_), manifest.dump(2) + "\n");
  return store;
}

RunStore RunStore::resume(const fs::path& folder, std::uint64_t seed,
                          const std::vector<RunPlan>& plans) {
  if (!fs::is_directory(folder)) {
    throw InputError(fmt::format(
        "command line: --resume: '{}' is not a folder; give the --out folder of the interrupted "
        "session",
        folder.string()));
  }
  RunStore store(checkpoint_directory(folder), seed);
  const fs::path manifest = manifest_path(store.directory_);
  if (!fs::exists(manifest)) {
    throw InputError(fmt::format(
        "{}: not found: '{}' holds no interrupted session to resume (a session that finished "
        "removes its checkpoints); run without --resume",
        manifest.string(), folder.string()));
  }
  const std::string text = read_text_file(manifest, "the session manifest");
  nlohmann::json session;
  try {
    session = nlohmann::json::parse(text);
    if (session.at("format") != kManifestFormat || session.at("version") != kManifestVersion) {
      throw std::runtime_error(
          fmt::format("expected format {} version {}", kManifestFormat, kManifestVersion));
    }
    static_cast<void>(session.at("seed").get<std::uint64_t>());
    for (const auto& run : session.at("runs")) static_cast<void>(describe(run));
  } catch (const std::exception& e) {
    throw InputError(
        fmt::format("{}: not a session this pcbench can resume: {}", manifest.string(), e.what()));
  }
  const auto saved_seed = session.at("seed").get<std::uint64_t>();
  if (saved_seed != seed) {
    throw InputError(fmt::format(
        "{}: the interrupted session ran with seed {}, this one with seed {}; resume with --seed "
        "{}, or write to another --out",
        manifest.string(), saved_seed, seed, saved_seed));
  }
  check_same_runs(session.at("runs"), plans, manifest);
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(store.directory_)) {
    if (entry.is_regular_file() && is_saved_run_file(entry.path())) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());  // the first bad file named is the same every time
  for (const fs::path& file : files) {
    SavedRun run = read_checked(file, seed, plans);
    store.saved_.emplace(run.id, std::move(run));
  }
  return store;
}

const SavedRun* RunStore::find(const std::string& id) const {
  const auto it = saved_.find(id);
  return it == saved_.end() ? nullptr : &it->second;
}

const SavedRun* RunStore::restore(const std::string& id) {
  const SavedRun* saved = find(id);
  if (saved != nullptr) ++restored_;
  return saved;
}

void RunStore::save(const RunPlan& plan, const RunResult& result, std::ostream& err) {
  if (result.status != RunStatus::kOk && result.status != RunStatus::kInvalid) return;
  const SavedRun run{.id = plan.id,
                     .seed = seed_,
                     .samples = plan.samples,
                     .replicates = plan.replicates,
                     .pilot_samples = plan.pilot_samples,
                     .pilot_cpu_per_sample = plan.pilot_cpu_per_sample,
                     .result = result};
  try {
    write_file_atomically(file_of(plan.id), saved_run_text(run));
  } catch (const std::exception& e) {
    if (!warned_) {
      err << "pcbench: warning: cannot save finished runs for --resume: " << e.what() << "\n";
    }
    warned_ = true;
  }
}

void RunStore::discard(std::ostream& err) {
  std::error_code error;
  fs::remove_all(directory_, error);
  if (error) {
    err << "pcbench: warning: cannot remove " << directory_.string() << ": " << error.message()
        << "\n";
  }
}

}  // namespace pcbench
