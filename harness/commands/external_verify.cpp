#include "harness/commands/external_verify.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>

#include "base/errors.h"
#include "harness/plan/estimates_file.h"
#include "harness/run/diagnostics.h"
#include "harness/session/publish.h"
#include "harness/session/report.h"
#include "harness/verify/rounding_bound.h"
#include "harness/verify/statistics.h"

namespace pcbench {
namespace {

// The heavy-tail guard on replicate estimates: k̂ and the largest share of Σ d² for the
// deviations d from the median. The effective-sample guard does not apply (each replicate is
// one number, already an average).
SampleDiagnostics diagnose_estimates(const std::vector<double>& estimates) {
  SampleDiagnostics d;
  d.min_effective_samples = std::numeric_limits<double>::infinity();
  d.nonzero = estimates.size();
  if (estimates.size() < kMinReplicatesForTail) return d;
  std::vector<double> sorted = estimates;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::vector<double> deviations;
  double squares = 0.0;
  for (double x : estimates) {
    deviations.push_back(std::fabs(x - median));
    squares += (x - median) * (x - median);
  }
  std::sort(deviations.begin(), deviations.end(), std::greater<>());
  const TailShape tail = pareto_tail_shape(deviations, deviations.size());
  d.tail_shape = tail.k;
  d.tail_size = tail.tail_size;
  d.largest_share = squares > 0.0 ? deviations.front() * deviations.front() / squares : 0.0;
  return d;
}

std::vector<ReplicateResult> as_replicates(const std::vector<double>& estimates) {
  std::vector<ReplicateResult> replicates;
  for (double x : estimates) {
    // Without per-sample data the scale of a small bias is taken as |estimate|.
    replicates.push_back({.estimate = x, .mean_abs = std::fabs(x), .n = 1});
  }
  return replicates;
}

}  // namespace

void check_external_request(const ExternalRequest& request) {
  if (request.reference.has_value() == request.against.has_value()) {
    throw InputError(
        "command line: --estimates needs exactly one of --reference V[±U] and --against FILE");
  }
}

EstimatesVerification verify_estimates(const std::vector<double>& estimates,
                                       const std::vector<double>& other,
                                       const ExternalRequest& request,
                                       const SessionOptions& options) {
  const SampleDiagnostics diagnostics = diagnose_estimates(estimates);

  Verdict verdict;
  nlohmann::json reference_json = nullptr;
  if (request.reference) {
    const ReferenceValue value = parse_reference(*request.reference);
    const Reference reference{
        .value = value.value,
        .kind = value.uncertainty > 0.0 ? ReferenceKind::kNumerical : ReferenceKind::kExact,
        .uncertainty = value.uncertainty};
    verdict = test_against_reference(as_replicates(estimates), reference, request.expect,
                                     kDecimalRoundings);
    reference_json = {{"value", value.value}, {"uncertainty", value.uncertainty}};
  } else {
    const double bound = rounding_bound(as_replicates(estimates), kDecimalRoundings) +
                         rounding_bound(as_replicates(other), kDecimalRoundings);
    verdict = two_sample_verdict(with_rounding_floor(welch_two_sample(estimates, other), bound),
                                 request.expect);
  }
  if (const std::optional<std::string> reason = untestable_reason(diagnostics)) {
    verdict = untested_verdict(*reason, request.expect);
  }
  std::vector<Verdict*> family = {&verdict};
  decide_family(family, options.alpha);

  double mean = 0.0;
  for (double x : estimates) mean += x / static_cast<double>(estimates.size());
  return {.verdict = verdict,
          .mean = mean,
          .external = {{"estimates_file", request.estimates},
                       {"replicates", estimates.size()},
                       {"mean", mean},
                       {"reference", reference_json},
                       {"against_file",
                        request.against ? nlohmann::json(*request.against) : nlohmann::json()},
                       {"against_replicates", other.size()},
                       {"tail_shape", std::isfinite(diagnostics.tail_shape)
                                          ? nlohmann::json(diagnostics.tail_shape)
                                          : nlohmann::json()},
                       {"verdict", verdict_to_json(verdict)}}};
}

int run_external_verification(const ExternalRequest& request, const SessionOptions& options,
                              std::ostream& out, std::ostream& err) {
  check_external_request(request);
  const std::vector<double> estimates = read_estimates(request.estimates, request.run_id);
  const std::vector<double> other =
      request.against ? read_estimates(*request.against) : std::vector<double>{};
  const EstimatesVerification verification = verify_estimates(estimates, other, request, options);
  const Verdict& verdict = verification.verdict;
  out << fmt::format(
      "{} estimates from {}: mean {:.6g}; {} ({}); minimum detectable bias {:.3g}{}\n",
      estimates.size(), request.estimates, verification.mean, verdict.result, verdict.reason,
      verdict.min_detectable_bias,
      estimates.size() < kMinReplicatesForTail
          ? fmt::format(" (tail not checked: fewer than {} replicates)", kMinReplicatesForTail)
          : std::string());
  ReportSections sections;
  sections.external.push_back(verification.external);
  if (!publish_report(options, sections, out, err)) return kExitRunFailed;
  return verdict.result == verdict.expect ? kExitOk : kExitVerdictDiffers;
}

}  // namespace pcbench
