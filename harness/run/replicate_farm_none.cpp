// A build without MPI (PCBENCH_MPI off; harness/replicate_farm.h): always one rank, no farm.
#include "harness/run/replicate_farm.h"

namespace pcbench {

void start_ranks(int* /*argc*/, char*** /*argv*/) {}
int rank_count() {
  return 1;
}
int this_rank() {
  return 0;
}
bool farms_command(const std::vector<std::string>& /*args*/) {
  return false;
}
ReplicateFarm* replicate_farm(const std::vector<RunPlan>& /*plans*/) {
  return nullptr;
}
int serve_replicates(const std::vector<RunPlan>& /*plans*/,
                     const std::atomic<bool>* /*interrupted*/) {
  return 0;
}
int stop_ranks(int status, const std::string& /*why*/) {
  return status;
}

}  // namespace pcbench
