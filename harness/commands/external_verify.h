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
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/session/session.h"
#include "harness/verify/statistics.h"

namespace pcbench {

inline constexpr std::size_t kMinReplicatesForTail = 50;

struct ExternalRequest {
  std::string estimates;                      // the file of replicate estimates
  std::optional<std::string> run_id = {};     // the run, when the file is a pcbench report
  std::optional<std::string> reference = {};  // "V", "V±U", "V+-U"
  std::optional<std::string> against = {};    // a second file of estimates
  std::string expect = "consistent";
};

// The request's own check: exactly one of a reference and a second set. Throws InputError.
void check_external_request(const ExternalRequest& request);

// Replicate estimates tested: the verdict (decided at options.alpha), their mean and their
// entry of the report's `external` section.
struct EstimatesVerification {
  Verdict verdict;
  double mean = 0.0;
  nlohmann::json external;
};

// The test of `estimates` (read and checked: finite, at least two) against request.reference,
// or two-sample against `other` when request.against names it; the CLI and the Python module
// call this alike. Throws InputError for a malformed reference. Writes nothing.
EstimatesVerification verify_estimates(const std::vector<double>& estimates,
                                       const std::vector<double>& other,
                                       const ExternalRequest& request,
                                       const SessionOptions& options);

// Reads, tests, writes the report and prints the verdict; bad input throws InputError before
// anything is written. Exit status as for `run`.
int run_external_verification(const ExternalRequest& request, const SessionOptions& options,
                              std::ostream& out, std::ostream& err);

}  // namespace pcbench
