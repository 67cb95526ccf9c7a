// "Bring your own estimates": replicate estimates of one quantity made outside pcbench (a user's
// renderer, say), read from a file so that pcbench can test them; and the pcbench reports those
// files may be.
//
// Every problem is an InputError whose message starts with the location: `FILE:LINE:COLUMN:` in
// CSV and text files and for JSON syntax errors, `FILE: /json/pointer:` inside a JSON document,
// and `FILE:` for the file as a whole (missing, unreadable, unknown extension).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pcbench {

// The extensions read_estimates understands (lower case; matched case-insensitively).
inline constexpr const char* kEstimatesExtensions[] = {".csv", ".txt", ".json"};

// The R independent replicate estimates in `file`, in file order; at least 2, all finite (a
// non-finite estimate is an error naming the replicate, never dropped). By extension:
// - .csv, .txt: one number per line; or comma-separated rows under a header row that names a
//   column `estimate` (other columns are ignored; a field may be double-quoted). Blank lines and
//   lines starting with '#' are skipped.
// - .json: an array of numbers; an object whose key "estimates" holds one; or a pcbench report,
//   whose run `run_id` supplies replicates[].estimate. Without `run_id` the report must hold
//   exactly one run, and it must be ok; otherwise the error lists the run ids to pick from.
// `run_id` is only valid for a pcbench report.
std::vector<double> read_estimates(const std::filesystem::path& file,
                                   const std::optional<std::string>& run_id = std::nullopt);

// Estimates given as numbers (the Python module's arrays), checked as a file's are: all finite
// (the first that is not named) and at least 2. Throws InputError starting with `name`.
void check_estimates(const std::vector<double>& estimates, const std::string& name);

// A reference value given on the command line: `V`, `V±U`, `V+-U` or `V+/-U`, where U is the
// standard uncertainty of V (>= 0; 0 when absent). Whitespace around the text and around the
// separator is allowed. Anything else is an InputError that names the text and the forms.
struct ReferenceValue {
  double value = {};
  double uncertainty = {};
};
ReferenceValue parse_reference(std::string_view text);

// ---------------------------------------------------------------------------------------------
// pcbench reports (results/report.schema.json), as far as estimates and comparisons need them.

struct ReportRun {
  std::string id = {};
  std::string estimator = {};  // "" when absent
  std::string integrand = {};  // "" when absent
  std::string status = {};     // ok | invalid | error | not_run
  std::string error = {};      // "" when null or absent
  // replicates[].estimate of an ok run (finite: a null estimate in an ok run is an error); empty
  // for runs that are not ok.
  std::vector<double> estimates = {};
};

struct ReportData {
  std::vector<ReportRun> runs = {};        // in report order; ids are unique
  std::optional<std::uint64_t> seed = {};  // context.seed, when present
};

// Reads a pcbench report: schema_version must be 1, runs[] objects with a unique string `id` and
// a known `status`. Other fields are not checked (readers ignore fields they do not know).
ReportData read_report(const std::filesystem::path& file);

}  // namespace pcbench
