#include "harness/plan/estimates_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "base/errors.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;
using Values = std::vector<double>;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Writes `text` to `name` in `folder` and reads its estimates.
Values read_written(const TemporaryFolder& folder, const std::string& name, const std::string& text,
                    const std::optional<std::string>& run_id = std::nullopt) {
  write_text(folder.path() / name, text);
  return read_estimates(folder.path() / name, run_id);
}

// ---------------------------------------------------------------------------------------------
// Accepted formats

TEST(EstimatesFileText, OneNumberPerLine) {
  TemporaryFolder folder;
  EXPECT_EQ(read_written(folder, "e.txt", "0.5\n0.25\n1e-3\n-2\n7\n"),
            (Values{0.5, 0.25, 1e-3, -2.0, 7.0}));
  // Blank lines, comments, CRLF, blanks around a number, a '+' sign, no final newline.
  EXPECT_EQ(read_written(folder, "e.txt", "# renderer v2\r\n\r\n  0.5 \r\n\t+0.25\r\n# end\n-1.5"),
            (Values{0.5, 0.25, -1.5}));
  // .csv with a single unnamed column is read the same way.
  EXPECT_EQ(read_written(folder, "e.csv", "1\n2\n"), (Values{1.0, 2.0}));
}

TEST(EstimatesFileCsv, HeaderNamingTheEstimateColumn) {
  TemporaryFolder folder;
  EXPECT_EQ(read_written(folder, "e.csv", "replicate,estimate,seconds\n0,0.5,1.2\n1,0.75,1.1\n"),
            (Values{0.5, 0.75}));
  // Other columns may hold anything, quoted fields may hold commas and quotes, blanks around
  // cells are ignored, and a UTF-8 byte order mark (Excel) is skipped.
  EXPECT_EQ(read_written(folder, "e.csv",
                         "\xEF\xBB\xBF"
                         "scene , \"estimate\",note\n"
                         "\"cornell, 64spp\", 1.5 ,\"said \"\"hi\"\"\"\n"
                         "# a comment\n"
                         "\n"
                         "cornell,\"2.5\",\n"),
            (Values{1.5, 2.5}));
  // A header naming only `estimate`; an unnamed first column (a pandas index).
  EXPECT_EQ(read_written(folder, "e.csv", "estimate\n3\n4\n"), (Values{3.0, 4.0}));
  EXPECT_EQ(read_written(folder, "e.csv", ",estimate\n0,3\n1,4\n"), (Values{3.0, 4.0}));
}

TEST(EstimatesFileCsv, ExtensionIsMatchedWithoutRegardToCase) {
  TemporaryFolder folder;
  EXPECT_EQ(read_written(folder, "E.CSV", "1\n2\n"), (Values{1.0, 2.0}));
  EXPECT_EQ(read_written(folder, "e.Json", "[1, 2]"), (Values{1.0, 2.0}));
}

TEST(EstimatesFileJson, ArrayAndObjectWithEstimates) {
  TemporaryFolder folder;
  EXPECT_EQ(read_written(folder, "e.json", "[0.5, 0.25, 1e-3, -2, 7]"),
            (Values{0.5, 0.25, 1e-3, -2.0, 7.0}));
  EXPECT_EQ(read_written(folder, "e.json",
                         R"({"renderer": "mine", "spp": 64, "estimates": [1.5, 2.5, 3]})"),
            (Values{1.5, 2.5, 3.0}));
}

TEST(EstimatesFileJson, ReportWithOneOkRun) {
  TemporaryFolder folder;
  const nlohmann::json report = small_report({small_report_run("0123456789abcdef", {0.5, 0.7})});
  EXPECT_EQ(read_written(folder, "report.json", report.dump(2)), (Values{0.5, 0.7}));
  // Naming the one run works too.
  EXPECT_EQ(read_written(folder, "report.json", report.dump(), "0123456789abcdef"),
            (Values{0.5, 0.7}));
}

TEST(EstimatesFileJson, ReportRunPickedById) {
  TemporaryFolder folder;
  const nlohmann::json report = small_report({small_report_run("0123456789abcdef", {0.5, 0.7}),
                                              small_report_run("fedcba9876543210", {1, 2, 3}),
                                              small_report_run("00000000000000ff", {}, "error")});
  EXPECT_EQ(read_written(folder, "report.json", report.dump(), "fedcba9876543210"),
            (Values{1.0, 2.0, 3.0}));
}

TEST(EstimatesFileReport, ReadReportKeepsRunsStatusesAndSeed) {
  TemporaryFolder folder;
  const nlohmann::json report =
      small_report({small_report_run("0123456789abcdef", {0.5, 0.7}),
                    small_report_run("00000000000000ff", {}, "error", "lvc", "door")},
                   42);
  write_text(folder.path() / "report.json", report.dump());
  const ReportData data = read_report(folder.path() / "report.json");
  ASSERT_EQ(data.runs.size(), 2u);
  EXPECT_EQ(data.seed, std::optional<std::uint64_t>(42));
  EXPECT_EQ(data.runs[0].id, "0123456789abcdef");
  EXPECT_EQ(data.runs[0].estimator, "plain");
  EXPECT_EQ(data.runs[0].status, "ok");
  EXPECT_EQ(data.runs[0].estimates, (Values{0.5, 0.7}));
  EXPECT_EQ(data.runs[1].estimator, "lvc");
  EXPECT_EQ(data.runs[1].integrand, "door");
  EXPECT_EQ(data.runs[1].status, "error");
  EXPECT_EQ(data.runs[1].error, "it failed");
  EXPECT_TRUE(data.runs[1].estimates.empty());
}

// ---------------------------------------------------------------------------------------------
// Bad input: every message starts with the location and says what was expected.

struct BadInput {
  const char* what;
  const char* file;  // written into a fresh folder unless `text` is null
  const char* text;
  const char* location;  // appended to the file's path: the message starts with the result
  const char* reason;    // the message contains it
  std::optional<std::string> run_id = std::nullopt;
};

std::string report_text(const std::vector<nlohmann::json>& runs, int version = 1) {
  nlohmann::json report = small_report(runs);
  report["schema_version"] = version;
  return report.dump(2);
}

const std::string kTwoRuns = report_text({small_report_run("0123456789abcdef", {0.5, 0.7}),
                                          small_report_run("fedcba9876543210", {1, 2})});
const std::string kErrorRun = report_text({small_report_run("0123456789abcdef", {}, "error")});
const std::string kVersion2 = report_text({small_report_run("0123456789abcdef", {1, 2})}, 2);
std::string ok_run_with_null() {
  nlohmann::json report = small_report({small_report_run("0123456789abcdef", {1, 2, 3})});
  report["runs"][0]["replicates"][1]["estimate"] = nullptr;
  return report.dump();
}
const std::string kOkRunWithNull = ok_run_with_null();

TEST(EstimatesFileErrors, EveryBadInputNamesItsLocationAndTheProblem) {
  const std::vector<BadInput> cases = {
      // The file as a whole.
      {"missing file", "missing.csv", nullptr, ": ",
       "cannot open the file of estimates: No such file or directory"},
      {"unknown extension", "e.dat", "1\n2\n", ": ",
       "unknown extension '.dat'; valid extensions: .csv, .txt, .json"},
      {"no extension", "estimates", "1\n2\n", ": ",
       "the file name has no extension; valid extensions: .csv, .txt, .json"},
      {"empty file", "e.csv", "", ":1:1: ", "the file holds no estimates"},
      {"only comments", "e.csv", "# nothing\n\n", ":3:1: ", "the file holds no estimates"},
      {"empty JSON file", "e.json", "  \n", ":1:1: ", "the file is empty"},
      // Cells.
      {"non-numeric line", "e.txt", "0.5\nabc\n0.25\n",
       ":2:1: ", "'abc' is not a number; expected a decimal number"},
      {"non-numeric estimate cell", "e.csv", "id,estimate\n0,0.5\n1, x1\n",
       ":3:4: ", "column 'estimate': 'x1' is not a number"},
      {"empty estimate cell", "e.csv", "a,estimate\nx,\ny,1\n",
       ":2:3: ", "column 'estimate': empty cell; expected a number"},
      {"NaN line", "e.txt", "0.5\nnan\n0.25\n", ":2:1: ",
       "replicate 1 (counting from 0) is 'nan', not a finite number; pcbench does not drop"},
      {"-inf cell", "e.csv", "estimate,x\n1,a\n2,b\n-inf,c\n",
       ":4:1: ", "column 'estimate': replicate 2 (counting from 0) is '-inf', not a finite number"},
      {"printf's -nan", "e.txt", "-nan\n1\n", ":1:1: ", "replicate 0 (counting from 0) is '-nan'"},
      {"overflowing number", "e.txt", "1\n1e999\n",
       ":2:1: ", "'1e999' is outside the range of a double"},
      {"one estimate", "e.csv", "estimate\n0.5\n",
       ":3:1: ", "1 estimate found (line 2); a test needs at least 2 replicate estimates"},
      {"header without rows", "e.csv", "estimate", ":1:9: ", "0 estimates found; a test needs"},
      // Structure.
      {"duplicate header column", "e.csv", "estimate,seconds,estimate\n1,2,3\n",
       ":1:18: ", "the header names column 'estimate' twice (columns 1 and 3)"},
      {"header without estimate", "e.csv", "value,seconds\n1,2\n3,4\n",
       ":1:1: ", "no column named 'estimate' (columns: 'value', 'seconds')"},
      {"row with too few cells", "e.csv", "id,estimate\n0,0.5\n1\n",
       ":3:1: ", "this row has 1 cell, the header (line 1) has 2"},
      {"several numbers, no header", "e.csv", "1,2\n3,4\n",
       ":1:1: ", "the first line holds 2 numbers and no header"},
      {"a comma in a one-column file", "e.txt", "0.5\n0.25 ,0.3\n",
       ":2:6: ", "expected one number per line, found 2 comma-separated cells"},
      {"unterminated quote", "e.csv", "name,estimate\n\"abc,0.5\n",
       ":2:1: ", "a quoted field has no closing '\"'"},
      // JSON.
      {"JSON syntax error", "e.json", "[1, 2,\n 3,]", ":2:", "JSON syntax error"},
      {"JSON null estimate", "e.json", "[0.5, null, 0.25]",
       ": /1: ", "replicate 1 is null: JSON has no NaN or infinity"},
      {"JSON string estimate", "e.json", R"({"estimates": [1, "2"]})",
       ": /estimates/1: ", "expected a number, found the string \"2\""},
      {"JSON object of the wrong shape", "e.json", R"({"values": [1, 2]})", ": /: ",
       "expected an array of numbers, an object with key \"estimates\", or a pcbench report (an "
       "object with \"runs\"); found an object with keys \"values\""},
      {"JSON number", "e.json", "3", ": /: ", "found the number 3"},
      {"JSON one estimate", "e.json", "[1.5]", ": /: ", "1 estimate found; a test needs"},
      {"JSON duplicate key", "e.json", R"({"estimates": [1, 2], "estimates": [3, 4]})",
       ": /estimates: ", "key 'estimates' appears twice in one object"},
      {"JSON nested duplicate key", "e.json", R"({"x": [0, {"k": 1, "k": 2}], "estimates": [])",
       ": /x/1/k: ", "key 'k' appears twice"},
      {"JSON overflowing number", "e.json", "[1e999, 1]", ":1:2: ", "number overflow"},
      // Reports.
      {"report with two runs", "r.json", kTwoRuns.c_str(), ": /runs: ",
       "the report has 2 runs; pick one by its id: 0123456789abcdef (plain on genz-gaussian, ok), "
       "fedcba9876543210 (plain on genz-gaussian, ok)"},
      {"report without the run asked for", "r.json", kTwoRuns.c_str(),
       ": /runs: ", "no run with id 'ffffffffffffffff'; the report's runs: 0123456789abcdef",
       "ffffffffffffffff"},
      {"report whose run failed", "r.json", kErrorRun.c_str(), ": /runs/0/status: ",
       "has status error: it failed; only an ok run's estimates can be tested"},
      {"report of schema_version 2", "r.json", kVersion2.c_str(),
       ": /schema_version: ", "pcbench reads reports of schema_version 1; this one has 2"},
      {"ok run with a null estimate", "r.json", kOkRunWithNull.c_str(),
       ": /runs/0/replicates/1/estimate: ", "null (non-finite) in a run whose status is ok"},
      {"run id for a CSV file", "e.csv", "1\n2\n", ": ",
       "a run id ('0123456789abcdef') selects a run of a pcbench report", "0123456789abcdef"},
      {"run id for a JSON array", "e.json", "[1, 2]", ": ", "this file is not one",
       "0123456789abcdef"},
  };
  for (const BadInput& bad : cases) {
    SCOPED_TRACE(bad.what);
    TemporaryFolder folder;
    const fs::path file = folder.path() / bad.file;
    if (bad.text != nullptr) write_text(file, bad.text);
    std::string message;
    try {
      read_estimates(file, bad.run_id);
      ADD_FAILURE() << "no error";
      continue;
    } catch (const InputError& e) {
      message = e.what();
    }
    const std::string location = file.string() + bad.location;
    EXPECT_TRUE(message.starts_with(location)) << message << "\ndoes not start with " << location;
    EXPECT_TRUE(contains(message, bad.reason)) << message << "\ndoes not say " << bad.reason;
  }
}

TEST(EstimatesFileErrors, FolderIsNotAFile) {
  TemporaryFolder folder;
  fs::create_directory(folder.path() / "dir.csv");
  try {
    read_estimates(folder.path() / "dir.csv");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (folder.path() / "dir.csv").string() +
                                         ": cannot read the file of estimates: Is a directory");
  }
}

TEST(EstimatesFileErrors, ReadReportRefusesDuplicateRunIdsAndUnknownStatus) {
  TemporaryFolder folder;
  const fs::path file = folder.path() / "r.json";
  write_text(file, report_text({small_report_run("0123456789abcdef", {1, 2}),
                                small_report_run("0123456789abcdef", {3, 4})}));
  EXPECT_THROW(
      {
        try {
          read_report(file);
        } catch (const InputError& e) {
          EXPECT_TRUE(std::string(e.what()).starts_with(file.string() + ": /runs/1/id: "));
          EXPECT_TRUE(contains(e.what(), "appears twice (also /runs/0/id)")) << e.what();
          throw;
        }
      },
      InputError);
  write_text(file, report_text({small_report_run("0123456789abcdef", {1, 2}, "fine")}));
  EXPECT_THROW(
      {
        try {
          read_report(file);
        } catch (const InputError& e) {
          EXPECT_TRUE(contains(e.what(),
                               ": /runs/0/status: unknown status 'fine'; valid: ok, "
                               "invalid, error, not_run"))
              << e.what();
          throw;
        }
      },
      InputError);
}

// ---------------------------------------------------------------------------------------------
// Reference values

TEST(EstimatesReference, AcceptedForms) {
  struct Case {
    const char* text;
    double value;
    double uncertainty;
  };
  const std::vector<Case> cases = {
      {"0.5", 0.5, 0.0},           {"  0.5\t", 0.5, 0.0},      {"+2", 2.0, 0.0},
      {"-1e-3", -1e-3, 0.0},       {"0.5±0.01", 0.5, 0.01},    {" 0.5 ± 0.01 ", 0.5, 0.01},
      {"0.5+-0.01", 0.5, 0.01},    {"0.5 +- 1e-2", 0.5, 0.01}, {"0.5+/-0.01", 0.5, 0.01},
      {"-3 +/- 0.25", -3.0, 0.25}, {"3±0", 3.0, 0.0},          {"3±+0.5", 3.0, 0.5},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const ReferenceValue reference = parse_reference(c.text);
    EXPECT_EQ(reference.value, c.value);
    EXPECT_EQ(reference.uncertainty, c.uncertainty);
  }
}

TEST(EstimatesReference, BadTextIsNamedWithTheAcceptedForms) {
  struct Case {
    const char* text;
    const char* reason;
  };
  const std::vector<Case> cases = {
      {"", "empty"},
      {"   ", "empty"},
      {"abc", "does not start with a number"},
      {"0.5 ± -0.01", "the uncertainty -0.01 is negative"},
      {"0.5+--0.01", "the uncertainty -0.01 is negative"},
      {"nan", "the value is not finite"},
      {"inf±1", "the value is not finite"},
      {"1±inf", "the uncertainty is not finite"},
      {"1e999", "outside the range of a double"},
      {"0.5 0.01", "unexpected '0.01' after the value"},
      {"0.5x", "unexpected 'x' after the value"},
      {"0.5±", "no uncertainty after '±'"},
      {"0.5+-", "no uncertainty after '+-'"},
      {"0.5±abc", "'abc' after '±' is not a number"},
      {"0.5±0.01 junk", "unexpected 'junk' after the uncertainty"},
      {"0.5±0.01±0.02", "unexpected '±0.02' after the uncertainty"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    try {
      parse_reference(c.text);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_TRUE(message.starts_with(std::string("reference '") + c.text + "': ")) << message;
      EXPECT_TRUE(contains(message, c.reason)) << message;
      EXPECT_TRUE(contains(message, "accepted forms: V, V±U, V+-U, V+/-U")) << message;
    }
  }
}

}  // namespace
}  // namespace pcbench
