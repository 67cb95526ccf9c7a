// The fuzz targets' inputs replayed through the same entry points (fuzz/fuzz_inputs.h), without
// libFuzzer: every input that once crashed a target (fuzz/regressions/<target>/) must now be
// accepted or rejected with an InputError, and the seed corpora (fuzz/corpus/<target>/) must keep
// saying what their names say (bad-* rejected, the rest accepted), so that they still reach past
// the parsers when the formats change.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "fuzz/fuzz_inputs.h"
#include "tests/test_support.h"

namespace pcbench::fuzz {
namespace {

namespace fs = std::filesystem;

const char* const kTargets[] = {"suite", "scene", "expression"};

const char* outcome_name(Outcome outcome) {
  return outcome == Outcome::kAccepted ? "accepted" : "rejected";
}

// Runs every file under fuzz/<kind>/<target>/ through the target's check; returns how many.
template <typename OnOutcome>
std::size_t replay(const std::string& kind, OnOutcome on_outcome) {
  const TemporaryFolder scratch;
  std::size_t count = 0;
  for (const char* target : kTargets) {
    const fs::path folder = fs::path(PCBENCH_SOURCE_DIR) / "fuzz" / kind / target;
    if (!fs::is_directory(folder)) continue;
    for (const std::string& file : files_under(folder)) {
      SCOPED_TRACE(fmt::format("fuzz/{}/{}/{}", kind, target, file));
      const std::string text = read_text(folder / file);
      // An exception other than InputError fails the test with its message; a crash or a
      // sanitizer report (the asan group) fails the test binary.
      try {
        on_outcome(file, check_input(target, text, scratch.path()));
      } catch (const std::exception& e) {
        ADD_FAILURE() << "unexpected exception: " << e.what();
      } catch (...) {
        ADD_FAILURE() << "unexpected exception of a type not derived from std::exception";
      }
      ++count;
    }
  }
  return count;
}

TEST(FuzzRegressions, EveryInputIsAcceptedOrRejectedCleanly) {
  const std::size_t count = replay("regressions", [](const std::string&, Outcome) {});
  EXPECT_GT(count, 0u) << "fuzz/regressions/ is empty or missing";
}

TEST(FuzzCorpus, SeedsAreAcceptedUnlessNamedBad) {
  const std::size_t count = replay("corpus", [](const std::string& file, Outcome outcome) {
    const Outcome expected = file.starts_with("bad-") ? Outcome::kRejected : Outcome::kAccepted;
    EXPECT_EQ(outcome, expected) << "the seed was " << outcome_name(outcome);
  });
  EXPECT_GT(count, 0u) << "fuzz/corpus/ is empty or missing";
}

}  // namespace
}  // namespace pcbench::fuzz
