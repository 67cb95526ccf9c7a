#include "harness/session/publish.h"

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <ctime>
#include <ostream>
#include <stdexcept>

#include <unistd.h>

#include "base/atomic_file.h"

namespace pcbench {
namespace {

namespace fs = std::filesystem;

// results/runs/<UTC date-time>[-k]: a new folder name, never an existing one.
fs::path default_run_folder() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::array<char, 32> stamp{};
  std::strftime(stamp.data(), stamp.size(), "%Y%m%d-%H%M%S", &tm);
  const fs::path runs = fs::path("results") / "runs";
  fs::path folder = runs / stamp.data();
  for (int k = 2; fs::exists(folder); ++k) folder = runs / fmt::format("{}-{}", stamp.data(), k);
  return folder;
}

// Points results/latest at `folder`, replacing the old link atomically.
void update_latest_link(const fs::path& folder) {
  const fs::path link = fs::path("results") / "latest";
  const fs::path temporary = fs::path("results") / fmt::format(".latest.{}", ::getpid());
  std::error_code ignored;
  fs::remove(temporary, ignored);
  fs::create_directory_symlink(fs::relative(folder, "results"), temporary);
  std::error_code error;
  fs::rename(temporary, link, error);
  if (error) {
    fs::remove(temporary, ignored);
    throw std::runtime_error(link.string() + ": " + error.message());
  }
}

}  // namespace

fs::path report_folder(const SessionOptions& options) {
  return options.out_dir ? fs::path(*options.out_dir) : default_run_folder();
}

Context session_context(const SessionOptions& options) {
  return gather_context(options.argv, options.seed, options.threads);
}

bool publish_report(const SessionOptions& options, const fs::path& folder, const Context& context,
                    const std::vector<RunRecord>& runs, const ReportSections& sections,
                    std::ostream& out, std::ostream& err) {
  const std::string report = report_json(context, options.suite_name, runs, sections);
  const fs::path report_path = folder / "report.json";
  try {
    write_file_atomically(report_path, report);
  } catch (const std::exception& e) {
    err << "pcbench: error: cannot write the report " << report_path.string() << ": " << e.what()
        << "\n";
    return false;
  }
  if (!options.out_dir) {
    try {
      update_latest_link(folder);
    } catch (const std::exception& e) {
      // The report is written; only the convenience link failed.
      err << "pcbench: warning: results/latest not updated: " << e.what() << "\n";
    }
  }
  out << "report: " << report_path.string() << "\n";
  return true;
}

bool publish_report(const SessionOptions& options, const ReportSections& sections,
                    std::ostream& out, std::ostream& err) {
  return publish_report(options, report_folder(options), session_context(options), {}, sections,
                        out, err);
}

}  // namespace pcbench
