// `pcbench calibrate` on an analytic integrand: prints and writes the self-test of the run test
// that harness/verify/run_calibration.h computes, and what both self-tests (this one and the
// block pyramid's, harness/commands/tile_calibration.h) share on the way to a report.
#pragma once

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <ostream>

#include "harness/session/report.h"
#include "harness/session/session.h"
#include "harness/verify/run_calibration.h"

namespace pcbench {

// The report's optional top-level `calibration` object ($defs/calibration in
// results/report.schema.json). Non-finite numbers (none expected) are written as null.
nlohmann::ordered_json calibration_json(const CalibrationResult& result);

// A human summary: the size table, then the power curve.
void print_calibration(const CalibrationResult& result, std::ostream& out);

// `pcbench calibrate`: runs calibrate(), prints it, writes a report whose `calibration` holds
// it. Exit 0 when it passes, 1 when it does not.
// What `pcbench calibrate` does with either self-test (this one,
// harness/commands/tile_calibration.h): runs `compute` (CalibrationInterrupted: exit 130, no
// report), prints the result unless quiet, publishes a report whose `section` holds its JSON, exit
// 0 when it passes and 1 when not.
template <class Compute, class Print, class ToSection>
int run_self_test(const char* suite, std::uint64_t first_seed, const SessionOptions& session,
                  std::ostream& out, std::ostream& err, Compute compute, Print print,
                  ToSection to_section) {
  decltype(compute()) result;
  try {
    result = compute();
  } catch (const CalibrationInterrupted&) {
    err << "pcbench: calibration interrupted: no report (the self-test needs all its seeds)\n";
    return kExitInterrupted;
  }
  if (!session.quiet) print(result, out);
  ReportSections sections;
  to_section(result, sections);
  return publish_self_test(suite, sections, result.pass, first_seed, session, out, err);
}

// Publishes a self-test's report and says where; the exit status as above.
int publish_self_test(const char* suite, const ReportSections& sections, bool pass,
                      std::uint64_t first_seed, const SessionOptions& session, std::ostream& out,
                      std::ostream& err);

int run_calibration(const CalibrationOptions& options, const SessionOptions& session,
                    std::ostream& out, std::ostream& err);

}  // namespace pcbench
