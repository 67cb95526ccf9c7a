// `pcbench verify --estimates FILE`: the verifier on replicate estimates from any renderer.
//
// A user's renderer made R independent replicate estimates of one quantity (one per line of a
// CSV, a JSON array, or a run of a pcbench report). They are tested against `--reference V±U`
// (Student t, or Welch when U > 0) or against a second file of estimates (two-sample Welch),
// with the same verdict, minimum detectable bias at 80% power and tail diagnostic as a run.
// The tail diagnostic looks at the replicate estimates themselves (their deviations from the
// median): a per-sample variance that is infinite leaves replicate means with the same heavy
// tail. It needs at least kMinReplicatesForTail replicates.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

#include "harness/session/session.h"

namespace pcbench {

inline constexpr std::size_t kMinReplicatesForTail = 50;

struct ExternalRequest {
  std::string estimates;                      // the file of replicate estimates
  std::optional<std::string> run_id = {};     // the run, when the file is a pcbench report
  std::optional<std::string> reference = {};  // "V", "V±U", "V+-U"
  std::optional<std::string> against = {};    // a second file of estimates
  std::string expect = "consistent";
};

// Reads, tests, writes the report and prints the verdict; bad input throws InputError before
// anything is written. Exit status as for `run`.
int run_external_verification(const ExternalRequest& request, const SessionOptions& options,
                              std::ostream& out, std::ostream& err);

}  // namespace pcbench
