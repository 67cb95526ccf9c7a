#include "harness/plan/estimates_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <utility>

#include "base/errors.h"
#include "base/json_input.h"
#include "base/text_file.h"

namespace pcbench {
namespace {

using Json = JsonInput::Json;

constexpr const char* kNeedTwo = "a test needs at least 2 replicate estimates";

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool is_blank(char c) {
  return c == ' ' || c == '\t';
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && (is_blank(text.front()) || text.front() == '\r')) text.remove_prefix(1);
  while (!text.empty() && (is_blank(text.back()) || text.back() == '\r')) text.remove_suffix(1);
  return text;
}

// Shortens what a message quotes.
std::string excerpt(std::string_view text) {
  constexpr std::size_t kMax = 40;
  if (text.size() <= kMax) return std::string(text);
  return std::string(text.substr(0, kMax)) + "...";
}

// "nan", "-nan", "NaN(123)", "inf", "-Infinity", ...: words for non-finite numbers.
bool names_nonfinite(std::string_view text) {
  if (!text.empty() && (text.front() == '+' || text.front() == '-')) text.remove_prefix(1);
  const std::string word = lower(text);
  return word.starts_with("nan") || word == "inf" || word == "infinity";
}

// Parses a number at the start of `text` (an optional '+' is allowed before a digit or '.').
// Returns the characters consumed, 0 when `text` does not start with a number; sets
// `out_of_range` when it does but does not fit a double.
std::size_t parse_number_prefix(std::string_view text, double& value, bool& out_of_range) {
  out_of_range = false;
  std::size_t skip = 0;
  if (text.size() >= 2 && text[0] == '+' &&
      (std::isdigit(static_cast<unsigned char>(text[1])) || text[1] == '.')) {
    skip = 1;
  }
  const char* begin = text.data() + skip;
  const auto [end, error] = std::from_chars(begin, text.data() + text.size(), value);
  if (error == std::errc::invalid_argument) return 0;
  out_of_range = error == std::errc::result_out_of_range;
  return static_cast<std::size_t>(end - text.data());
}

std::string nonfinite_problem(std::size_t replicate, const std::string& text) {
  return fmt::format(
      "replicate {} (counting from 0) is '{}', not a finite number; pcbench does not drop "
      "non-finite estimates: find out why the renderer produced it",
      replicate, text);
}

// What is wrong with `text` as one finite estimate ("" if nothing): `value` is set when not.
std::string number_problem(std::string_view text, std::size_t replicate, double& value) {
  if (text.empty()) return "empty cell; expected a number";
  if (names_nonfinite(text)) return nonfinite_problem(replicate, excerpt(text));
  bool out_of_range = false;
  const std::size_t used = parse_number_prefix(text, value, out_of_range);
  if (used != text.size() || used == 0) {
    return fmt::format("'{}' is not a number; expected a decimal number such as 0.25 or 1e-3",
                       excerpt(text));
  }
  if (out_of_range) return fmt::format("'{}' is outside the range of a double", excerpt(text));
  return "";
}

std::string too_few(std::size_t count, const std::string& where = "") {
  return fmt::format("{} {} found{}; {}", count, count == 1 ? "estimate" : "estimates", where,
                     kNeedTwo);
}

// ---------------------------------------------------------------------------------------------
// CSV and text

struct Field {
  std::string text;
  std::size_t column = 0;  // 1-based, of the field's first non-blank character
};

class DelimitedParser {
 public:
  DelimitedParser(std::string name, std::string_view text) : name_(std::move(name)), text_(text) {}

  std::vector<double> parse() {
    if (text_.starts_with("\xEF\xBB\xBF")) text_.remove_prefix(3);  // a UTF-8 byte order mark
    std::vector<double> estimates;
    std::size_t line_number = 0, first_value_line = 0;
    std::size_t start = 0;
    bool header_read = false, single_column = false;
    while (start <= text_.size()) {
      std::size_t end = text_.find('\n', start);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(start, end - start);
      if (line.ends_with('\r')) line.remove_suffix(1);
      ++line_number;
      start = end + 1;
      const std::string_view content = trim(line);
      if (content.empty() || content.front() == '#') continue;
      const std::vector<Field> fields = split(line, line_number);

      if (!header_read && !single_column) {
        double ignored = 0.0;
        bool out_of_range = false;
        const auto numeric = [&](const Field& f) {
          return names_nonfinite(f.text) ||
                 (!f.text.empty() &&
                  parse_number_prefix(f.text, ignored, out_of_range) == f.text.size());
        };
        if (fields.size() == 1 && numeric(fields[0])) {
          single_column = true;  // no header: one number per line
        } else if (std::all_of(fields.begin(), fields.end(), numeric)) {
          fail(line_number, 1,
               fmt::format("the first line holds {} numbers and no header; a file with several "
                           "columns needs a header row naming the 'estimate' column",
                           fields.size()));
        } else {
          read_header(fields, line_number);
          header_read = true;
          continue;
        }
      }

      const Field* cell = nullptr;
      if (single_column) {
        if (fields.size() != 1) {
          fail(line_number, line.find(',') + 1,
               fmt::format("expected one number per line, found {} comma-separated cells (a "
                           "file with several columns needs a header row naming the 'estimate' "
                           "column)",
                           fields.size()));
        }
        cell = &fields[0];
      } else {
        if (fields.size() != header_.size()) {
          fail(line_number, 1,
               fmt::format("this row has {} cell{}, the header (line {}) has {}", fields.size(),
                           fields.size() == 1 ? "" : "s", header_line_, header_.size()));
        }
        cell = &fields[estimate_column_];
      }
      double value = 0.0;
      const std::string problem = number_problem(cell->text, estimates.size(), value);
      if (!problem.empty()) {
        fail(line_number, cell->column,
             single_column ? problem : fmt::format("column 'estimate': {}", problem));
      }
      if (estimates.empty()) first_value_line = line_number;
      estimates.push_back(value);
    }
    if (estimates.size() < 2) {
      std::string what =
          too_few(estimates.size(),
                  estimates.size() == 1 ? fmt::format(" (line {})", first_value_line) : "");
      if (estimates.empty() && !header_read)
        what = fmt::format("the file holds no estimates; {}", what);
      const auto [line, column] = end_position();
      fail(line, column, what);
    }
    return estimates;
  }

 private:
  [[noreturn]] void fail(std::size_t line, std::size_t column, const std::string& why) const {
    throw InputError(fmt::format("{}:{}:{}: {}", name_, line, column, why));
  }

  // Comma-separated fields; a field may be double-quoted ("" inside for a quote).
  std::vector<Field> split(std::string_view line, std::size_t line_number) const {
    std::vector<Field> fields;
    std::size_t i = 0;
    const std::size_t n = line.size();
    while (true) {
      while (i < n && is_blank(line[i])) ++i;
      Field field;
      field.column = i + 1;
      if (i < n && line[i] == '"') {
        ++i;
        while (true) {
          if (i >= n) fail(line_number, field.column, "a quoted field has no closing '\"'");
          if (line[i] == '"') {
            if (i + 1 < n && line[i + 1] == '"') {
              field.text += '"';
              i += 2;
              continue;
            }
            ++i;
            break;
          }
          field.text += line[i++];
        }
        while (i < n && is_blank(line[i])) ++i;
        if (i < n && line[i] != ',') {
          fail(line_number, i + 1, "expected ',' or the end of the line after a quoted field");
        }
      } else {
        std::size_t end = line.find(',', i);
        if (end == std::string_view::npos) end = n;
        field.text = std::string(trim(line.substr(i, end - i)));
        i = end;
      }
      fields.push_back(std::move(field));
      if (i >= n) break;
      ++i;  // the comma
    }
    return fields;
  }

  void read_header(const std::vector<Field>& fields, std::size_t line_number) {
    std::map<std::string, std::size_t> seen;  // name -> column number (1-based)
    for (std::size_t c = 0; c < fields.size(); ++c) {
      const std::string& name = fields[c].text;
      if (name.empty()) continue;  // an unnamed column (an index, say) cannot be 'estimate'
      const auto [it, inserted] = seen.emplace(name, c + 1);
      if (!inserted) {
        fail(line_number, fields[c].column,
             fmt::format("the header names column '{}' twice (columns {} and {})", excerpt(name),
                         it->second, c + 1));
      }
    }
    const auto found = std::find_if(fields.begin(), fields.end(),
                                    [](const Field& f) { return f.text == "estimate"; });
    if (found == fields.end()) {
      std::vector<std::string> names;
      for (const Field& f : fields) names.push_back(fmt::format("'{}'", excerpt(f.text)));
      fail(line_number, 1,
           fmt::format("the first line is not a number, so it is read as a header row, but it "
                       "has no column named 'estimate' (columns: {}); expected one number per "
                       "line, or a header row naming an 'estimate' column",
                       join_names(names)));
    }
    header_.clear();
    for (const Field& f : fields) header_.push_back(f.text);
    estimate_column_ = static_cast<std::size_t>(found - fields.begin());
    header_line_ = line_number;
  }

  // Line and column just past the last character.
  std::pair<std::size_t, std::size_t> end_position() const {
    const std::size_t lines =
        static_cast<std::size_t>(std::count(text_.begin(), text_.end(), '\n'));
    const std::size_t last_newline = text_.rfind('\n');
    const std::size_t column =
        last_newline == std::string_view::npos ? text_.size() + 1 : text_.size() - last_newline;
    return {lines + 1, column};
  }

  std::string name_;
  std::string_view text_;
  std::vector<std::string> header_;
  std::size_t estimate_column_ = 0;
  std::size_t header_line_ = 0;
};

// ---------------------------------------------------------------------------------------------
// JSON

std::string kind_of(const Json& value) {
  if (value.is_null()) return "null";
  if (value.is_boolean()) return fmt::format("the boolean {}", value.dump());
  if (value.is_string()) return fmt::format("the string {}", excerpt(value.dump()));
  if (value.is_number()) return fmt::format("the number {}", value.dump());
  if (value.is_array()) return "an array";
  return "an object";
}

// The numbers of a JSON array of estimates at `pointer`.
std::vector<double> estimates_array(const JsonInput& in, const Json& array,
                                    const std::string& pointer) {
  if (!array.is_array()) {
    in.fail(pointer, fmt::format("expected an array of numbers, found {}", kind_of(array)));
  }
  std::vector<double> estimates;
  for (std::size_t i = 0; i < array.size(); ++i) {
    const Json& item = array[i];
    const std::string at = fmt::format("{}/{}", pointer, i);
    if (item.is_null()) {
      in.fail(at,
              fmt::format("replicate {} is null: JSON has no NaN or infinity, so a null stands "
                          "for a non-finite estimate, and pcbench does not drop those; find out "
                          "why the renderer produced it",
                          i));
    }
    if (!item.is_number()) {
      in.fail(at, fmt::format("expected a number, found {}", kind_of(item)));
    }
    estimates.push_back(item.get<double>());
  }
  if (estimates.size() < 2) in.fail(pointer, too_few(estimates.size()));
  return estimates;
}

std::string describe(const ReportRun& run) {
  std::string what = run.id + " (";
  if (!run.estimator.empty() || !run.integrand.empty()) {
    what += fmt::format("{} on {}, ", run.estimator, run.integrand);
  }
  return what + run.status + ")";
}

std::string run_list(const ReportData& report) {
  std::vector<std::string> runs;
  for (const ReportRun& run : report.runs) runs.push_back(describe(run));
  return join_names(runs);
}

// A string member of a report's object: "" when absent (or null, where it is optional).
std::string string_member(const JsonInput& in, const Json& object, const std::string& pointer,
                          const char* key, bool required) {
  if (!object.contains(key) || (!required && object[key].is_null())) {
    if (required) in.fail(fmt::format("{}/{}", pointer, key), "missing");
    return "";
  }
  const Json& value = object[key];
  if (!value.is_string()) {
    in.fail(fmt::format("{}/{}", pointer, key),
            fmt::format("expected a string, found {}", kind_of(value)));
  }
  return value.get<std::string>();
}

// The runs of a pcbench report, once its header says it is one: an object of schema_version 1
// with an array of runs.
const Json& report_runs(const JsonInput& in, const Json& root) {
  if (!root.is_object()) {
    in.fail("", fmt::format("expected a pcbench report (an object), found {}", kind_of(root)));
  }
  if (!root.contains("schema_version")) {
    in.fail("/schema_version", "missing; a pcbench report has \"schema_version\": 1");
  }
  const Json& version = root["schema_version"];
  if (!version.is_number_integer() || version.get<std::int64_t>() != 1) {
    in.fail("/schema_version",
            fmt::format("pcbench reads reports of schema_version 1; this one has {}",
                        excerpt(version.dump())));
  }
  if (!root.contains("runs")) in.fail("/runs", "missing; a pcbench report has \"runs\"");
  const Json& runs = root["runs"];
  if (!runs.is_array()) {
    in.fail("/runs", fmt::format("expected an array of runs, found {}", kind_of(runs)));
  }
  return runs;
}

// The replicate estimates of an ok run at `at`. pcbench marks a run with a non-finite estimate
// invalid, so a null estimate in an ok run means the report was altered.
std::vector<double> ok_run_estimates(const JsonInput& in, const Json& run, const std::string& at) {
  if (!run.contains("replicates") || !run["replicates"].is_array()) {
    in.fail(at + "/replicates", "an ok run needs an array of replicates");
  }
  const Json& replicates = run["replicates"];
  std::vector<double> estimates;
  for (std::size_t r = 0; r < replicates.size(); ++r) {
    const std::string rep_at = fmt::format("{}/replicates/{}", at, r);
    const Json& replicate = replicates[r];
    if (!replicate.is_object() || !replicate.contains("estimate")) {
      in.fail(rep_at, "expected a replicate object with an \"estimate\"");
    }
    const Json& estimate = replicate["estimate"];
    if (estimate.is_null()) {
      in.fail(rep_at + "/estimate",
              "null (non-finite) in a run whose status is ok; pcbench marks a run with a "
              "non-finite estimate invalid, so this report has been altered");
    }
    if (!estimate.is_number()) {
      in.fail(rep_at + "/estimate", fmt::format("expected a number, found {}", kind_of(estimate)));
    }
    estimates.push_back(estimate.get<double>());
  }
  return estimates;
}

// Run `i` of a report: a unique non-empty id (`index_of_id` holds the ids read so far), a known
// status, and the estimates of an ok run.
ReportRun report_run(const JsonInput& in, const Json& run, std::size_t i,
                     std::map<std::string, std::size_t>& index_of_id) {
  const std::string at = fmt::format("/runs/{}", i);
  if (!run.is_object()) in.fail(at, fmt::format("expected a run object, found {}", kind_of(run)));
  ReportRun out;
  out.id = string_member(in, run, at, "id", true);
  if (out.id.empty()) in.fail(at + "/id", "empty run id");
  const auto [it, inserted] = index_of_id.emplace(out.id, i);
  if (!inserted) {
    in.fail(at + "/id",
            fmt::format("run id '{}' appears twice (also /runs/{}/id)", out.id, it->second));
  }
  out.estimator = string_member(in, run, at, "estimator", false);
  out.integrand = string_member(in, run, at, "integrand", false);
  out.status = string_member(in, run, at, "status", true);
  constexpr const char* kStatuses[] = {"ok", "invalid", "error", "not_run"};
  if (std::find(std::begin(kStatuses), std::end(kStatuses), out.status) == std::end(kStatuses)) {
    in.fail(at + "/status", fmt::format("unknown status '{}'; valid: {}", excerpt(out.status),
                                        join_names(kStatuses)));
  }
  out.error = string_member(in, run, at, "error", false);
  if (out.status == "ok") out.estimates = ok_run_estimates(in, run, at);
  return out;
}

ReportData report_from_json(const JsonInput& in, const Json& root) {
  const Json& runs = report_runs(in, root);
  ReportData report;
  std::map<std::string, std::size_t> index_of_id;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    report.runs.push_back(report_run(in, runs[i], i, index_of_id));
  }
  if (root.contains("context") && root["context"].is_object() && root["context"].contains("seed") &&
      root["context"]["seed"].is_number_unsigned()) {
    report.seed = root["context"]["seed"].get<std::uint64_t>();
  }
  return report;
}

std::vector<double> estimates_of_report(const JsonInput& in, const ReportData& report,
                                        const std::optional<std::string>& run_id) {
  std::size_t index = 0;
  if (run_id) {
    const auto found = std::find_if(report.runs.begin(), report.runs.end(),
                                    [&](const ReportRun& run) { return run.id == *run_id; });
    if (found == report.runs.end()) {
      in.fail("/runs", report.runs.empty()
                           ? fmt::format("no run with id '{}': the report has no runs", *run_id)
                           : fmt::format("no run with id '{}'; the report's runs: {}", *run_id,
                                         run_list(report)));
    }
    index = static_cast<std::size_t>(found - report.runs.begin());
  } else if (report.runs.size() != 1) {
    in.fail("/runs", report.runs.empty()
                         ? std::string("the report has no runs")
                         : fmt::format("the report has {} runs; pick one by its id: {}",
                                       report.runs.size(), run_list(report)));
  }
  const ReportRun& run = report.runs[index];
  const std::string at = fmt::format("/runs/{}", index);
  if (run.status != "ok") {
    in.fail(at + "/status",
            fmt::format("run {} has status {}{}; only an ok run's estimates can be tested",
                        describe(run), run.status,
                        run.error.empty() ? "" : fmt::format(": {}", run.error)));
  }
  if (run.estimates.size() < 2) in.fail(at + "/replicates", too_few(run.estimates.size()));
  return run.estimates;
}

}  // namespace

std::vector<double> read_estimates(const std::filesystem::path& file,
                                   const std::optional<std::string>& run_id) {
  const std::string name = file.string();
  const std::string extension = lower(file.extension().string());
  const bool known = std::any_of(std::begin(kEstimatesExtensions), std::end(kEstimatesExtensions),
                                 [&](const char* valid) { return extension == valid; });
  if (!known) {
    throw InputError(fmt::format(
        "{}: {}; valid extensions: {}", name,
        extension.empty() ? std::string("the file name has no extension")
                          : fmt::format("unknown extension '{}'", file.extension().string()),
        join_names(kEstimatesExtensions)));
  }
  const std::string text = read_text_file(file, "the file of estimates");
  if (extension != ".json") {
    if (run_id) {
      throw InputError(
          fmt::format("{}: a run id ('{}') selects a run of a pcbench report (.json); "
                      "this file is not one",
                      name, *run_id));
    }
    return DelimitedParser(name, text).parse();
  }
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(
        fmt::format("{}:1:1: the file is empty; expected an array of numbers, an "
                    "object with key \"estimates\", or a pcbench report",
                    name));
  }
  const JsonInput in(name);
  const Json root = in.parse(text);
  const bool is_report = root.is_object() && root.contains("runs");
  if (run_id && !is_report) {
    throw InputError(
        fmt::format("{}: a run id ('{}') selects a run of a pcbench report; this "
                    "file is not one (it has no \"runs\")",
                    name, *run_id));
  }
  if (root.is_array()) return estimates_array(in, root, "");
  if (root.is_object() && is_report) {
    if (root.contains("estimates")) {
      in.fail("", "has both \"runs\" (a pcbench report) and \"estimates\"; keep one");
    }
    return estimates_of_report(in, report_from_json(in, root), run_id);
  }
  if (root.is_object() && root.contains("estimates")) {
    return estimates_array(in, root["estimates"], "/estimates");
  }
  std::string found = kind_of(root);
  if (root.is_object()) {
    std::vector<std::string> keys;
    for (const auto& item : root.items())
      keys.push_back(fmt::format("\"{}\"", excerpt(item.key())));
    found =
        keys.empty() ? "an empty object" : fmt::format("an object with keys {}", join_names(keys));
  }
  in.fail("", fmt::format("expected an array of numbers, an object with key \"estimates\", or a "
                          "pcbench report (an object with \"runs\"); found {}",
                          found));
}

void check_estimates(const std::vector<double>& estimates, const std::string& name) {
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    if (!std::isfinite(estimates[i])) {
      throw InputError(
          fmt::format("{}: {}", name, nonfinite_problem(i, fmt::format("{}", estimates[i]))));
    }
  }
  if (estimates.size() < 2)
    throw InputError(fmt::format("{}: {}", name, too_few(estimates.size())));
}

ReportData read_report(const std::filesystem::path& file) {
  const std::string name = file.string();
  const std::string text = read_text_file(file, "the report");
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(fmt::format("{}:1:1: the file is empty; expected a pcbench report", name));
  }
  const JsonInput in(name);
  return report_from_json(in, in.parse(text));
}

ReferenceValue parse_reference(std::string_view text) {
  const auto fail = [&](const std::string& why) {
    throw InputError(
        fmt::format("reference '{}': {}; accepted forms: V, V±U, V+-U, V+/-U, where U >= 0 is the "
                    "standard uncertainty of V (e.g. 0.5 or 0.5±0.002)",
                    excerpt(text), why));
  };
  std::string_view rest = trim(text);
  if (rest.empty()) fail("empty");
  ReferenceValue reference;
  bool out_of_range = false;
  std::size_t used = parse_number_prefix(rest, reference.value, out_of_range);
  if (used == 0) fail("does not start with a number");
  if (out_of_range) fail("the value is outside the range of a double");
  if (!std::isfinite(reference.value)) fail("the value is not finite");
  rest = trim(rest.substr(used));
  if (rest.empty()) return reference;
  std::string_view separator;
  for (const std::string_view candidate : {"\xC2\xB1", "+/-", "+-"}) {
    if (rest.starts_with(candidate)) {
      separator = candidate;
      break;
    }
  }
  if (separator.empty()) fail(fmt::format("unexpected '{}' after the value", excerpt(rest)));
  rest = trim(rest.substr(separator.size()));
  if (rest.empty()) fail(fmt::format("no uncertainty after '{}'", separator));
  used = parse_number_prefix(rest, reference.uncertainty, out_of_range);
  if (used == 0) fail(fmt::format("'{}' after '{}' is not a number", excerpt(rest), separator));
  if (out_of_range) fail("the uncertainty is outside the range of a double");
  if (!std::isfinite(reference.uncertainty)) fail("the uncertainty is not finite");
  if (!trim(rest.substr(used)).empty()) {
    fail(fmt::format("unexpected '{}' after the uncertainty", excerpt(trim(rest.substr(used)))));
  }
  if (reference.uncertainty < 0.0) {
    fail(fmt::format("the uncertainty {} is negative", reference.uncertainty));
  }
  return reference;
}

}  // namespace pcbench
