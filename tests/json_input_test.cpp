// The JSON input reader shared by the suite, scene and estimates readers (base/json_input.h), and
// the whole-file reader behind all of them (base/text_file.h).
#include "base/json_input.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "base/errors.h"
#include "base/text_file.h"
#include "harness/plan/suite_file.h"
#include "tests/test_support.h"

namespace pcbench {
namespace {

using Json = JsonInput::Json;

// The InputError message of `action`, or "" when it does not throw.
std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(JsonInput, RepeatedKeyIsRefusedAtItsPointer) {
  const JsonInput in("in.json");
  EXPECT_EQ(error_of([&] { in.parse(R"({"a": [0, {"k": 1, "k": 2}]})"); }),
            "in.json: /a/1/k: key 'k' appears twice in one object");
  EXPECT_EQ(error_of([&] { in.parse(R"({"k": 1, "k": 1})"); }),
            "in.json: /k: key 'k' appears twice in one object");
  // The same key in two different objects is no repeat.
  EXPECT_NO_THROW(in.parse(R"({"a": {"k": 1}, "b": {"k": 1}, "k": [{"k": 1}, {"k": 2}]})"));
}

TEST(JsonInput, PointersEscapeSlashAndTilde) {
  const JsonInput in("in.json");
  EXPECT_EQ(JsonInput::member("/params", "a/b~c"), "/params/a~1b~0c");
  EXPECT_EQ(error_of([&] { in.parse(R"({"x/y": {"m~n": 1, "m~n": 2}})"); }),
            "in.json: /x~1y/m~0n: key 'm~n' appears twice in one object");
  const Json object = in.parse(R"({"a/b": 1})");
  EXPECT_EQ(error_of([&] { in.check_keys(object, "/o", {"ab"}); }),
            "in.json: /o/a~1b: unknown key 'a/b'; valid keys: ab (did you mean 'ab'?)");
}

TEST(JsonInput, UnknownKeyNamesTheValidKeysAndTheNearest) {
  const JsonInput in("in.json");
  const Json object = in.parse(R"({"samples": 1, "replicats": 2})");
  EXPECT_EQ(error_of([&] {
              in.check_keys(object, "", {"samples", "replicates", "seed"});
            }),
            "in.json: /replicats: unknown key 'replicats'; valid keys: samples, replicates, seed "
            "(did you mean 'replicates'?)");
  // No suggestion when nothing is near.
  const Json far = in.parse(R"({"zzzzzz": 1})");
  EXPECT_EQ(error_of([&] {
              in.check_keys(far, "/d", {"samples", "seed"});
            }),
            "in.json: /d/zzzzzz: unknown key 'zzzzzz'; valid keys: samples, seed");
}

TEST(JsonInput, IntegersOutsideTheirRangeOrNotIntegersAreRefused) {
  const JsonInput in("in.json");
  EXPECT_EQ(in.integer_at(Json(7), "/n", 1, 7), 7u);
  EXPECT_EQ(error_of([&] { in.integer_at(Json(8), "/n", 1, 7); }),
            "in.json: /n: must be an integer in [1, 7]; 8 is out of range");
  EXPECT_EQ(error_of([&] { in.integer_at(Json(-1), "/n", 0, 7); }),
            "in.json: /n: must be an integer in [0, 7]; -1 is out of range");
  EXPECT_EQ(error_of([&] { in.integer_at(Json(1.5), "/n", 0, 7); }),
            "in.json: /n: must be an integer in [0, 7], not 1.5");
  EXPECT_EQ(error_of([&] { in.integer_at(Json("5"), "/n", 0, 7); }),
            "in.json: /n: must be an integer in [0, 7], not \"5\"");
}

TEST(JsonInput, WrongTypesNameTheValueFound) {
  const JsonInput in("in.json");
  EXPECT_EQ(error_of([&] { in.string_at(Json(5), "/name"); }),
            "in.json: /name: must be a string, not 5");
  EXPECT_EQ(error_of([&] { in.boolean_at(Json("yes"), "/b"); }),
            "in.json: /b: must be true or false, not \"yes\"");
  EXPECT_EQ(error_of([&] { in.number_at(Json(nullptr), "/x"); }),
            "in.json: /x: must be a finite number, not null");
  EXPECT_EQ(error_of([&] { in.require_object(Json::array(), ""); }),
            "in.json: /: must be an object, not []");
  EXPECT_EQ(error_of([&] { in.require_array(Json::object(), "/runs"); }),
            "in.json: /runs: must be an array, not {}");
  EXPECT_EQ(error_of([&] { in.required(Json::object(), "/runs/0", "estimator"); }),
            "in.json: /runs/0: missing \"estimator\"");
  EXPECT_EQ(error_of([&] {
              in.choice_at(Json("pairwize"), "/c", "mode", {"pairwise", "none"});
            }),
            "in.json: /c: unknown mode 'pairwize'; valid: pairwise, none (did you mean "
            "'pairwise'?)");
  // A long value is cut in the message.
  const std::string message = error_of([&] { in.string_at(Json(std::vector<int>(50, 1)), "/s"); });
  EXPECT_TRUE(message.ends_with(",1,...")) << message;
}

TEST(JsonInput, SyntaxErrorsAndHugeNumbersHaveALineAndColumn) {
  const JsonInput in("in.json");
  EXPECT_TRUE(
      error_of([&] { in.parse("{\n  @\n}"); }).starts_with("in.json:2:3: JSON syntax error"));
  EXPECT_TRUE(error_of([&] { in.parse("{\n \"n\": 1e999}"); }).starts_with("in.json:2:7: "));
}

// The suite reader uses the shared reader: what only the scene reader did before (escaped
// pointers, suggestions) it does now.
TEST(JsonInput, SuiteReaderEscapesPointersAndSuggestsKeys) {
  const std::string escaped = error_of([] {
    parse_suite(R"({"runs": [{"estimator": "plain", "integrand": "genz-gaussian",
                              "params": {"a/b": {}}}]})",
                "suite.json");
  });
  EXPECT_TRUE(escaped.starts_with("suite.json: /runs/0/params/a~1b: must be a string or a number"))
      << escaped;
  const std::string suggested = error_of([] {
    parse_suite(R"({"runs": [{"estimator": "plain", "integrand": "genz-gaussian", "sample": 5}]})",
                "suite.json");
  });
  EXPECT_TRUE(suggested.ends_with("(did you mean 'samples'?)")) << suggested;
  const std::string repeated =
      error_of([] { parse_suite(R"({"runs": [], "runs": []})", "suite.json"); });
  EXPECT_EQ(repeated, "suite.json: /runs: key 'runs' appears twice in one object");
}

TEST(TextFile, ReadsEveryByte) {
  const TemporaryFolder folder;
  const std::string text("a\0b\r\n\xff", 6);
  write_text(folder.path() / "t.bin", text);
  EXPECT_EQ(read_text_file(folder.path() / "t.bin", "the test file"), text);
  write_text(folder.path() / "empty", "");
  EXPECT_EQ(read_text_file(folder.path() / "empty", "the test file"), "");
}

TEST(TextFile, MissingFileOrFolderNamesThePathAndTheReason) {
  const TemporaryFolder folder;
  const std::filesystem::path missing = folder.path() / "missing.json";
  EXPECT_EQ(error_of([&] { read_text_file(missing, "the suite file"); }),
            missing.string() + ": cannot open the suite file: No such file or directory");
  EXPECT_EQ(error_of([&] { read_text_file(folder.path(), "the suite file"); }),
            folder.path().string() + ": cannot read the suite file: Is a directory");
  // Through the suite reader's entry point.
  EXPECT_EQ(error_of([&] { load_suite(missing.string()); }),
            missing.string() + ": cannot open the suite file: No such file or directory");
}

}  // namespace
}  // namespace pcbench
