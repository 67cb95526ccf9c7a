// The ranks of an MPI job (`mpirun -np P pcbench run|verify|reference …`) sharing a session's
// replicates: the session asks the farm instead of execute_run, and gets the run execute_run
// would have given, bit for bit.
//
// Every replicate's numbers depend only on (seed, plan, replicate index) (harness/runner.h), so
// any rank can compute any replicate. Rank 0 announces the runs it is about to run; each
// replicate of them is a unit, numbered in order over the whole session, and unit u belongs to
// rank u mod P, so whole runs and the replicates of a run are spread alike and every rank knows
// its share without asking. The other ranks send each finished replicate (the RunResult of that
// one replicate, in the exact form of harness/saved_run.h) to rank 0, which appends them in
// replicate order with append_part, as interleaved runs do: no sum is ever formed in another
// order, and no MPI reduction touches a number.
//
// harness/run/replicate_farm_mpi.cpp implements it with MPI; a build without MPI (PCBENCH_MPI off)
// has harness/run/replicate_farm_none.cpp, where there is always one rank and no farm.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "harness/plan/plan.h"
#include "harness/run/runner.h"

namespace pcbench {

class ReplicateFarm {
 public:
  virtual ~ReplicateFarm() = default;
  // Rank 0: the runs about to run, in the order `run` will be asked for them, so that the other
  // ranks start on their share of all of them at once.
  virtual void announce(const std::vector<const RunPlan*>& runs, const RunnerOptions& options) = 0;
  // Rank 0: the run over all ranks; the same result as execute_run(plan, options). A run not
  // announced (or not next) is announced alone first.
  virtual RunResult run(const RunPlan& plan, const RunnerOptions& options) = 0;
};

// Starts MPI when this process is a rank of an MPI job (mpirun or srun set its environment);
// otherwise nothing. Call first in main().
void start_ranks(int* argc, char*** argv);
// The number of ranks (1 without MPI) and this one's (0 without MPI).
int rank_count();
int this_rank();
// Whether this command takes part in the job on every rank: run, verify and reference do; any
// other command runs on rank 0 alone.
bool farms_command(const std::vector<std::string>& args);

// Rank 0 of a job of more than one rank: the farm for the runs planned from the command line
// (every rank plans the same runs from the same arguments). Null otherwise.
ReplicateFarm* replicate_farm(const std::vector<RunPlan>& plans);

// Ranks other than 0: compute this rank's share of every run rank 0 announces, until rank 0
// stops. Returns the exit status.
int serve_replicates(const std::vector<RunPlan>& plans, const std::atomic<bool>* interrupted);

// The end of main() on every rank: rank 0 tells the others that no more runs come; a rank that
// stopped before serving (`why`: what it wrote) ends the job if rank 0 still wants its share.
// Then MPI ends. Returns `status`.
int stop_ranks(int status, const std::string& why);

}  // namespace pcbench
