// The replicate farm over MPI (harness/replicate_farm.h): built when PCBENCH_MPI is on.
//
// Messages, all on MPI_COMM_WORLD:
//   rank 0 → all (broadcast): a batch of announced runs, [n, then 7 numbers per run: the index
//     of the planned run it is made from, samples, id_hash, replicates, seed, strategy images,
//     stream_hash];
//     n = 0 ends the job.
//   rank k → rank 0 (tag kReplicateTag): one finished replicate, as saved_run_text, in unit order.
// Waiting polls with a short sleep instead of blocking: Open MPI spins in a blocking call, which
// would take a core from the ranks still computing (and from rank 0's equal-time pilots).
#include <mpi.h>

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <iterator>
#include <list>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

#include "harness/run/replicate_farm.h"
#include "harness/run/saved_run.h"

namespace pcbench {
namespace {

constexpr int kReplicateTag = 17;
constexpr std::size_t kFields = 7;
using RunFields = std::array<std::uint64_t, kFields>;

bool g_started = false;
int g_rank = 0;
int g_size = 1;
bool g_served = false;  // a rank > 0 that ran serve_replicates to its end

void pause_briefly() {
  std::this_thread::sleep_for(std::chrono::microseconds(500));
}

void wait_for(MPI_Request& request) {
  int done = 0;
  for (MPI_Test(&request, &done, MPI_STATUS_IGNORE); !done;
       MPI_Test(&request, &done, MPI_STATUS_IGNORE)) {
    pause_briefly();
  }
}

// Rank 0 → all: a batch of runs (empty: the end).
void broadcast_batch(std::vector<RunFields>& runs) {
  std::uint64_t count = runs.size();
  MPI_Request request{};
  MPI_Ibcast(&count, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &request);
  wait_for(request);
  if (count == 0) return;
  runs.resize(count);
  MPI_Ibcast(runs.data(), static_cast<int>(count * kFields), MPI_UINT64_T, 0, MPI_COMM_WORLD,
             &request);
  wait_for(request);
}

std::string receive_text(int source) {
  MPI_Status status{};
  int found = 0;
  for (MPI_Iprobe(source, kReplicateTag, MPI_COMM_WORLD, &found, &status); !found;
       MPI_Iprobe(source, kReplicateTag, MPI_COMM_WORLD, &found, &status)) {
    pause_briefly();
  }
  int size = 0;
  MPI_Get_count(&status, MPI_CHAR, &size);
  std::string text(static_cast<std::size_t>(size), '\0');
  MPI_Recv(text.data(), size, MPI_CHAR, source, kReplicateTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return text;
}

int owner_of(std::uint64_t unit) {
  return static_cast<int>(unit % static_cast<std::uint64_t>(g_size));
}

// The planned run a run to run is made from (equal-time choices, escalation stages and reference
// renders are copies of a planned run with another budget or streams): the one sharing its
// built estimator and integrand.
std::size_t planned_index(const std::vector<RunPlan>& plans, const RunPlan& plan) {
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const RunPlan& p = plans[i];
    if (p.estimator == plan.estimator && p.integrand == plan.integrand &&
        p.made_estimator == plan.made_estimator && p.made_integrand == plan.made_integrand &&
        p.render == plan.render) {
      return i;
    }
  }
  throw std::logic_error("replicate farm: a run not made from a planned run");
}

// The run a batch entry names, as every rank rebuilds it from the same plans.
RunPlan rebuilt(const std::vector<RunPlan>& plans, const RunFields& fields) {
  if (fields[0] >= plans.size()) throw std::logic_error("replicate farm: unknown planned run");
  RunPlan plan = plans[fields[0]];
  plan.samples = fields[1];
  plan.id_hash = fields[2];
  plan.replicates = static_cast<std::uint32_t>(fields[3]);
  plan.stream_hash = fields[6];
  return plan;
}

RunnerOptions one_replicate(RunnerOptions options, std::uint32_t replicate) {
  options.first_replicate = replicate;
  options.replicate_count = 1;
  return options;
}

class MpiFarm final : public ReplicateFarm {
 public:
  explicit MpiFarm(std::vector<RunPlan> plans) : plans_(std::move(plans)) {}

  void announce(const std::vector<const RunPlan*>& runs, const RunnerOptions& options) override {
    drain();
    std::vector<RunFields> batch;
    for (const RunPlan* plan : runs) batch.push_back(fields_of(*plan, options));
    if (batch.empty()) return;
    broadcast_batch(batch);
    for (const RunFields& fields : batch) {
      pending_.push_back({fields, next_unit_});
      next_unit_ += fields[3];
    }
  }

  RunResult run(const RunPlan& plan, const RunnerOptions& options) override {
    const RunFields fields = fields_of(plan, options);
    if (pending_.empty() || pending_.front().fields != fields) announce({&plan}, options);
    const Announced next = pending_.front();
    pending_.pop_front();
    // This rank's replicates first, then the others' as they come, then all in replicate order.
    std::vector<std::optional<RunResult>> parts(plan.replicates);
    for (std::uint32_t r = 0; r < plan.replicates; ++r) {
      if (owner_of(next.first_unit + r) == 0)
        parts[r] = execute_run(plan, one_replicate(options, r));
    }
    for (std::uint32_t r = 0; r < plan.replicates; ++r) {
      const int owner = owner_of(next.first_unit + r);
      if (owner == 0) continue;
      parts[r] = read_saved_run(receive_text(owner)).result;
      if (options.samples_done != nullptr) options.samples_done->fetch_add(plan.samples);
    }
    if (parts.empty()) return execute_run(plan, options);
    RunResult result = std::move(*parts[0]);
    for (std::uint32_t r = 1; r < plan.replicates; ++r) append_part(result, std::move(*parts[r]));
    return result;
  }

  // Receives (and drops) the replicates of announced runs that were not asked for (a session
  // interrupted before them): the other ranks send them anyway.
  void drain() {
    for (const Announced& a : pending_) {
      for (std::uint64_t r = 0; r < a.fields[3]; ++r) {
        if (owner_of(a.first_unit + r) != 0) receive_text(owner_of(a.first_unit + r));
      }
    }
    pending_.clear();
  }

 private:
  struct Announced {
    RunFields fields;
    std::uint64_t first_unit = 0;
  };

  RunFields fields_of(const RunPlan& plan, const RunnerOptions& options) const {
    return {planned_index(plans_, plan),
            plan.samples,
            plan.id_hash,
            plan.replicates,
            options.seed,
            options.strategy_images ? 1u : 0u,
            plan.stream_hash};
  }

  std::vector<RunPlan> plans_;
  std::deque<Announced> pending_;
  std::uint64_t next_unit_ = 0;
};

std::unique_ptr<MpiFarm> g_farm;

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

}  // namespace

void start_ranks(int* argc, char*** argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  // Only the main thread calls MPI; TBB's threads compute.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_started = true;
}

int rank_count() {
  return g_size;
}
int this_rank() {
  return g_rank;
}

bool farms_command(const std::vector<std::string>& args) {
  return !args.empty() && (args[0] == "run" || args[0] == "verify" || args[0] == "reference");
}

ReplicateFarm* replicate_farm(const std::vector<RunPlan>& plans) {
  if (!g_started || g_size < 2 || g_rank != 0) return nullptr;
  g_farm = std::make_unique<MpiFarm>(plans);
  return g_farm.get();
}

int serve_replicates(const std::vector<RunPlan>& plans, const std::atomic<bool>* interrupted) {
  std::list<std::pair<std::string, MPI_Request>> sending;
  std::uint64_t unit = 0;
  for (;;) {
    std::vector<RunFields> batch;
    broadcast_batch(batch);
    if (batch.empty()) break;
    for (const RunFields& fields : batch) {
      const RunPlan plan = rebuilt(plans, fields);
      const RunnerOptions options{
          .seed = fields[4], .interrupted = interrupted, .strategy_images = fields[5] != 0};
      for (std::uint32_t r = 0; r < plan.replicates; ++r, ++unit) {
        if (owner_of(unit) != g_rank) continue;
        SavedRun part{.id = plan.id,
                      .seed = options.seed,
                      .samples = plan.samples,
                      .replicates = 1,
                      .result = execute_run(plan, one_replicate(options, r))};
        auto& [text, request] = sending.emplace_back(saved_run_text(part), MPI_Request{});
        MPI_Isend(text.data(), static_cast<int>(text.size()), MPI_CHAR, 0, kReplicateTag,
                  MPI_COMM_WORLD, &request);
        // Frees the texts rank 0 has taken.
        for (auto it = sending.begin(); it != sending.end();) {
          int done = 0;
          MPI_Test(&it->second, &done, MPI_STATUS_IGNORE);
          it = done ? sending.erase(it) : std::next(it);
        }
      }
    }
  }
  for (auto& [text, request] : sending) wait_for(request);
  g_served = true;
  return 0;
}

int stop_ranks(int status, const std::string& why) {
  if (!g_started) return status;
  if (g_rank == 0) {
    if (g_farm) g_farm->drain();
    std::vector<RunFields> end;
    broadcast_batch(end);
  } else if (!g_served) {
    std::vector<RunFields> batch;
    broadcast_batch(batch);
    if (!batch.empty()) {
      // Rank 0 is waiting for this rank's share, which will never come.
      std::fprintf(stderr, "pcbench: rank %d stopped before taking part (exit status %d): %s\n",
                   g_rank, status, why.c_str());
      MPI_Abort(MPI_COMM_WORLD, 3);
    }
  }
  g_farm.reset();
  MPI_Finalize();
  return g_rank == 0 ? status : 0;
}

}  // namespace pcbench
